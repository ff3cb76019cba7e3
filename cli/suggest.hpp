#pragma once
/// "Did you mean" for mistyped options: the closest option names of a (sub)command by edit
/// distance.

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace rt::cli {

/// Edit distance (ASCII): insertions, deletions, substitutions, adjacent transpositions.
int edit_distance(const std::string& a, const std::string& b);

/// The option of `candidates` closest to `typed` (e.g. "--robto" -> "--robot"), or "" when none
/// is close: at most 2 edits, and at most a third of the typed name; a unique candidate that
/// starts with `typed` also counts.
std::string closest_option(const std::string& typed, const std::vector<std::string>& candidates);

/// Every option name of `app` ("--robot", "-o", ...), help included.
std::vector<std::string> option_names(const CLI::App& app);

/// For a command line CLI11 rejected: one line per unknown option argument of the subcommand
/// named in argv (or of `app`), "unknown option '--robto' (did you mean '--robot'?)"; empty when
/// every option argument is known.
std::vector<std::string> unknown_option_hints(const CLI::App& app, int argc, const char* const* argv);

}  // namespace rt::cli
