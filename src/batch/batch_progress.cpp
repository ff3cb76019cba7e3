#include "retarget/batch/batch_progress.hpp"

#include <algorithm>
#include <cmath>

#include "retarget/core/strings.hpp"

namespace rt {

std::string format_duration(double seconds) {
  if (!(seconds >= 0) || !std::isfinite(seconds)) return "?";
  const long s = std::lround(seconds);
  if (s >= 3600) return format("%ldh%02ldm", s / 3600, (s % 3600) / 60);
  if (s >= 60) return format("%ldm%02lds", s / 60, s % 60);
  return format("%lds", s);
}

std::string format_progress_bar(const BatchProgress& p, int width) {
  std::string counts = format(" %d/%d  ok %d", p.done + p.failed, p.total, p.done);
  if (p.skipped > 0) counts += format(" (skipped %d)", p.skipped);
  counts += format("  failed %d  left %d", p.failed, p.remaining());
  if (p.running > 0) counts += format("  running %d", p.running);
  counts += "  ETA " + (p.remaining() == 0 ? std::string("0s") : format_duration(p.eta_s));
  // The bar takes what is left of the line, between 10 and 40 cells.
  const int cells = std::clamp(width - static_cast<int>(counts.size()) - 3, 10, 40);
  const double fraction = p.total > 0 ? static_cast<double>(p.done + p.failed) / p.total : 1.0;
  const int full = std::clamp(static_cast<int>(std::floor(fraction * cells)), 0, cells);
  std::string line = "[" + std::string(static_cast<std::size_t>(full), '#') + std::string(static_cast<std::size_t>(cells - full), '.') + "]" + counts;
  if (width > 0 && static_cast<int>(line.size()) > width) line.resize(static_cast<std::size_t>(width));
  return line;
}

std::string format_clip_line(const ClipResult& c, int finished, int total) {
  const int digits = static_cast<int>(std::to_string(total).size());
  std::string line = format("[%*d/%d] %-13s %s", digits, finished, total, clip_status_name(c.status), c.name.c_str());
  if (c.status != ClipStatus::Skipped) line += format("  %.1f s", c.time_s);
  if (c.check != CheckOutcome::NotRun) line += std::string("  check ") + check_outcome_name(c.check);
  if (!c.main_violation.empty() && c.check == CheckOutcome::Failed) line += " (" + c.main_violation + ")";
  if (!c.error.empty()) line += "  " + c.error;
  return line;
}

}  // namespace rt
