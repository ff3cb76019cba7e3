#include "cli/suggest.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <set>

namespace rt::cli {

int edit_distance(const std::string& a, const std::string& b) {
  // Optimal string alignment: insertions, deletions, substitutions and adjacent transpositions
  // ("--robto" is one edit from "--robot").
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::string closest_option(const std::string& typed, const std::vector<std::string>& candidates) {
  std::string best;
  int best_distance = 1 << 30;
  std::vector<std::string> prefixed;
  for (const std::string& c : candidates) {
    const int d = edit_distance(typed, c);
    if (d < best_distance) best = c, best_distance = d;
    if (c.size() > typed.size() && c.compare(0, typed.size(), typed) == 0) prefixed.push_back(c);
  }
  const int name_length = static_cast<int>(typed.size()) - (typed.rfind("--", 0) == 0 ? 2 : 1);
  if (best_distance <= 2 && 3 * best_distance <= std::max(name_length, 3)) return best;
  if (prefixed.size() == 1 && name_length >= 3) return prefixed.front();
  return "";
}

std::vector<std::string> option_names(const CLI::App& app) {
  std::vector<std::string> out;
  for (const CLI::Option* opt : app.get_options()) {
    for (const std::string& n : opt->get_lnames()) out.push_back("--" + n);
    for (const std::string& n : opt->get_snames()) out.push_back("-" + n);
  }
  return out;
}

std::vector<std::string> unknown_option_hints(const CLI::App& app, int argc, const char* const* argv) {
  const CLI::App* command = &app;
  int first = 1;
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] == '-') continue;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      if (sub->get_name() == argv[i]) command = sub, first = i + 1;
    break;
  }
  const std::vector<std::string> names = option_names(*command);
  const std::set<std::string> known(names.begin(), names.end());
  std::vector<std::string> hints;
  for (int i = first; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--") break;
    if (arg.size() < 2 || arg[0] != '-' || (arg[1] >= '0' && arg[1] <= '9') || arg[1] == '.') continue;  // values
    if (const auto eq = arg.find('='); eq != std::string::npos) arg.resize(eq);
    if (arg[1] != '-' && arg.size() > 2) arg.resize(2);  // -o<value>
    if (known.count(arg)) continue;
    const std::string guess = closest_option(arg, names);
    hints.push_back("unknown option '" + arg + "'" + (guess.empty() ? "" : " (did you mean '" + guess + "'?)") +
                    "; see 'retarget " + (command == &app ? std::string() : command->get_name() + " ") + "--help'");
  }
  return hints;
}

}  // namespace rt::cli
