// Checks on a tool's files before any work starts: an input must be a file (not a directory),
// and an output must not name an input or another output. Written under a temporary name and
// renamed over its target (core/atomic_output.h), an output that names an input replaces the
// input once the run succeeds; two outputs naming one file leave only the last.
#pragma once

#include <string>
#include <vector>

namespace sss {

// Before reading a whole file: throws Error("<path>: is a directory, not a file") or, for a
// FIFO, a device or a socket, Error("<path>: not a regular file") (a directory opens as a
// stream of unbounded size, a FIFO blocks); symlinks are followed. A missing path is left to
// the caller's open, which names it in its own terms.
void checkInputFile(const std::string& path);

// A file of a tool's command line: how errors call it (its option, "-o", "--json", or for a
// positional argument its role, "the mesh") and its path ("": not given, skipped).
struct ToolFile {
  std::string name;
  std::string path;
};

// Throws UsageError (core/tool.h: exit 2, the command line is wrong whatever the files hold)
// when an output is the same file as an input or as another output: the same path spelt
// differently ("./x", "d/../x"), a symlink or a hard link to it. Inputs that do not exist (a
// missing file the loader will report, a name such as "sky") are skipped; outputs that do not
// exist yet are compared by their canonical paths.
void checkOutputsAreNotInputs(const std::vector<ToolFile>& outputs,
                              const std::vector<ToolFile>& inputs);

}  // namespace sss
