#include "core/batch.h"

#include <exception>
#include <filesystem>
#include <map>
#include <new>
#include <system_error>

#include "core/error.h"
#include "core/tool.h"

namespace sss {

namespace fs = std::filesystem;

bool namesFolder(const std::string& path) {
  if (path.empty()) return false;
  std::error_code ec;
  return path.back() == '/' || fs::is_directory(path, ec);
}

bool isBatch(const std::vector<std::string>& inputs, const std::string& output) {
  return inputs.size() > 1 || namesFolder(output);
}

std::string batchOutputPath(const std::string& dir, const std::string& input,
                            const std::string& suffix) {
  return (fs::path(dir) / (fs::path(input).stem().string() + suffix)).string();
}

namespace {

void createFolder(const BatchOutput& output) {
  std::error_code ec;
  fs::create_directories(output.dir, ec);
  if (ec || !fs::is_directory(output.dir, ec)) {
    fail(output.dir, output.option + ": cannot create the output folder (" + ec.message() + ")");
  }
}

// Two inputs whose outputs would be one file (the same stem in one folder).
void checkStemsAreUnique(const std::vector<BatchItem>& items,
                         const std::vector<BatchOutput>& outputs) {
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    std::map<std::string, const std::string*> writer;  // output path -> input
    for (const BatchItem& item : items) {
      const std::string& out = item.outputs[k];
      if (out.empty()) continue;
      const fs::path key = fs::weakly_canonical(fs::absolute(out));
      const auto [it, inserted] = writer.emplace(key.string(), &item.input);
      if (!inserted) {
        throw UsageError(*it->second + " and " + item.input + " would both write " + out + " (" +
                         outputs[k].option + "): give inputs different names");
      }
    }
  }
}

}  // namespace

std::vector<BatchItem> planBatch(const std::vector<std::string>& inputs,
                                 const std::vector<BatchOutput>& outputs,
                                 const std::vector<ToolFile>& sharedInputs) {
  std::vector<BatchItem> items;
  std::vector<ToolFile> allInputs = sharedInputs;
  for (const std::string& input : inputs) {
    BatchItem item{input, {}};
    for (const BatchOutput& output : outputs) {
      item.outputs.push_back(
          output.dir.empty() ? std::string() : batchOutputPath(output.dir, input, output.suffix));
    }
    items.push_back(std::move(item));
    allInputs.push_back({"an input", input});
  }
  checkStemsAreUnique(items, outputs);
  for (const BatchItem& item : items) {
    std::vector<ToolFile> files;
    for (std::size_t k = 0; k < outputs.size(); ++k) {
      files.push_back({outputs[k].option, item.outputs[k]});
    }
    checkOutputsAreNotInputs(files, allInputs);
  }
  for (const BatchOutput& output : outputs) {
    if (!output.dir.empty()) createFolder(output);
  }
  return items;
}

int runBatch(const std::vector<BatchItem>& items,
             const std::function<void(const BatchItem&)>& process, bool quiet) {
  std::size_t failed = 0;
  for (const BatchItem& item : items) {
    try {
      process(item);
    } catch (const std::bad_alloc&) {
      printError(item.input + ": out of memory");
      ++failed;
    } catch (const std::exception& e) {
      const std::string message = e.what();
      // Loaders already start their messages with the file's name.
      printError(message.rfind(item.input, 0) == 0 ? message : item.input + ": " + message);
      ++failed;
    }
  }
  if (items.size() > 1 && failed > 0) {
    info(std::to_string(failed) + " of " + std::to_string(items.size()) + " inputs failed", quiet);
  }
  return failed > 0 ? kExitFailure : kExitOk;
}

}  // namespace sss
