// Several inputs in one process (`sss-bake a.ply b.obj -o DIR/`, `sss-irrmap *.exr -o DIR/`,
// `sss-render *.ply -e env.exr -o DIR/`): what is shared (the environment, the GL context, the
// ~0.2 s start-up of a process linked to OpenImageIO) is paid once, each input writes its own
// outputs under DIR, and one bad input does not stop the others.
//
//   if (isBatch(inputs, output)) {
//     const std::vector<BatchItem> items = planBatch(inputs, {{"-o", output, ".ply"}}, shared);
//     ... load what the inputs share ...
//     return runBatch(items, [&](const BatchItem& item) { process(item.input, item.outputs[0]); });
//   }
//
// A single input with an output file keeps the tools' single-input behaviour exactly.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/paths.h"

namespace sss {

// Batch mode: more than one input, or an output that names a folder (an existing directory or a
// path ending in '/').
bool isBatch(const std::vector<std::string>& inputs, const std::string& output);
bool namesFolder(const std::string& path);

// The output of `input` in folder `dir`: DIR/<stem><suffix>, suffix = "_irradiance.exr", ".ply",
// ... (the one place batch output names are made).
std::string batchOutputPath(const std::string& dir, const std::string& input,
                            const std::string& suffix);

// A kind of output in batch mode: its option, its folder ("" when not asked for) and the suffix
// each input's file gets there.
struct BatchOutput {
  std::string option;
  std::string dir;
  std::string suffix;
};

// One input and its outputs, in the order of the BatchOutputs given ("" where not asked for).
struct BatchItem {
  std::string input;
  std::vector<std::string> outputs;
};

// The items of a batch, checked before any work: every output folder exists (created when
// missing), an output never names an input (of the batch or `sharedInputs`) and two inputs never
// share an output (the same stem: a/x.ply and b/x.obj), each a UsageError (exit 2).
std::vector<BatchItem> planBatch(const std::vector<std::string>& inputs,
                                 const std::vector<BatchOutput>& outputs,
                                 const std::vector<ToolFile>& sharedInputs);

// Runs `process` on each item in order. An item's Error (or any exception but an interruption)
// prints one line "<tool>: error: <input>: <problem>" (the input named once) and the next item
// runs; its outputs are written atomically, so a failed item leaves none. Returns the exit
// status: 0 when every item succeeded, 1 (kExitFailure) when any failed; with more than one
// input a summary line "<n> of <m> inputs failed" follows unless quiet.
int runBatch(const std::vector<BatchItem>& items,
             const std::function<void(const BatchItem&)>& process, bool quiet);

}  // namespace sss
