// retarget merge-summaries: one summary (summary.json, summary.csv, index.html) from the summaries
// of the shards of a batch (`retarget batch --shard I/N`).

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/command.hpp"
#include "cli/exit_codes.hpp"
#include "retarget/batch/batch_summary.hpp"
#include "retarget/core/strings.hpp"

namespace rt::cli {

namespace {

struct MergeOptions {
  std::string out;
  std::vector<std::string> summaries;
};

}  // namespace

Command setup_merge_summaries(CLI::App& parent) {
  auto o = std::make_shared<MergeOptions>();
  CLI::App* app = parent.add_subcommand(
      "merge-summaries", "Combine the summaries of batch shards into one summary.json, summary.csv and index.html");
  app->add_option("out", o->out, "Output folder for the merged summary (links are rewritten relative to it)")->required();
  app->add_option("summaries", o->summaries, "Shard summaries (summary-shard-I-of-N.json or summary.json), or folders holding them")
      ->required();
  app->footer(
      "Exit status: that of the merged batch (0 all ok, 1 some check failed, 2 some clip failed otherwise),\n"
      "or 2 when a summary cannot be read or the summaries do not belong together.");
  return {app, [o] {
            namespace fs = std::filesystem;
            std::vector<std::string> paths;
            for (const std::string& s : o->summaries) {
              if (!fs::is_directory(s)) {
                paths.push_back(s);
                continue;
              }
              // A folder: its shard summaries, else its summary.json.
              std::vector<std::string> found;
              for (const auto& e : fs::directory_iterator(s)) {
                const std::string name = e.path().filename().string();
                if (starts_with(name, "summary-shard-") && ends_with(name, ".json")) found.push_back(e.path().string());
              }
              std::sort(found.begin(), found.end());
              if (found.empty()) found.push_back((fs::path(s) / "summary.json").string());
              paths.insert(paths.end(), found.begin(), found.end());
            }
            const BatchSummary merged = merge_summaries(paths, o->out);
            const std::vector<std::string> written = write_summary(o->out, merged);
            std::vector<std::string> parts;
            for (ClipStatus st : all_clip_statuses())
              if (const int n = merged.count(st)) parts.push_back(format("%d %s", n, clip_status_name(st)));
            std::cout << format("merged %zu summaries: %zu clip(s): ", paths.size(), merged.clips.size()) << join(parts, ", ")
                      << "\nwrote " << join(written, ", ") << "\n";
            return batch_exit_status(merged);
          }};
}

}  // namespace rt::cli
