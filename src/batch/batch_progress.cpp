#include "retarget/batch/batch_progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "retarget/core/strings.hpp"

namespace rt {

namespace {

// "Frames: N" on the first non-blank line after "MOTION"; the hierarchy before it is read line by
// line, up to 16 MiB (a skeleton is a few kB; this bounds a file that has no MOTION at all).
std::int64_t bvh_frames(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t read = 0;
  bool motion = false;
  while (read < (16u << 20) && std::getline(in, line)) {
    read += line.size() + 1;
    const std::string_view t = trim(line);
    if (t.empty()) continue;
    if (!motion) {
      motion = t == "MOTION";
      continue;
    }
    if (t.size() < 7 || t.substr(0, 7) != "Frames:") return 0;
    const std::string number(trim(t.substr(7)));
    char* end = nullptr;
    const long long n = std::strtoll(number.c_str(), &end, 10);
    return !number.empty() && *end == '\0' && n > 0 ? n : 0;
  }
  return 0;
}

// Header words 4 and 5 (first and last frame, 16 bit) in the byte order of the processor byte
// (byte 4 of the parameter section, whose 512-byte block number is header byte 1).
std::int64_t c3d_frames(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char header[512];
  if (!in.read(reinterpret_cast<char*>(header), sizeof header) || header[1] != 0x50 || header[0] < 1) return 0;
  unsigned char param[4];
  in.seekg(static_cast<std::streamoff>(header[0] - 1) * 512);
  if (!in.read(reinterpret_cast<char*>(param), sizeof param)) return 0;
  bool big_endian = false;
  if (param[3] == 86) big_endian = true;                        // MIPS
  else if (param[3] != 84 && param[3] != 85) return 0;          // Intel, DEC: little-endian words
  auto word = [&](int k) {  // 1-based 16-bit word k of the header
    const unsigned a = header[2 * (k - 1)], b = header[2 * (k - 1) + 1];
    return big_endian ? (a << 8 | b) : (b << 8 | a);
  };
  const unsigned first = word(4), last = word(5);
  if (first < 1 || last < first || last == 0xffff) return 0;  // 0xffff: a longer take, count unknown
  return static_cast<std::int64_t>(last - first + 1);
}

}  // namespace

std::int64_t probe_source_frames(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return 0;  // a FIFO would block the probe; the worker reports it
  const std::string ext = to_lower(std::filesystem::path(path).extension().string());
  if (ext == ".bvh") return bvh_frames(path);
  if (ext == ".c3d") return c3d_frames(path);
  return 0;
}

std::vector<double> source_frame_weights(const std::vector<BatchClip>& clips, const std::vector<std::int64_t>& probed) {
  double frames = 0, bytes = 0;
  for (std::size_t k = 0; k < clips.size() && k < probed.size(); ++k)
    if (probed[k] > 0) {
      frames += static_cast<double>(probed[k]);
      bytes += static_cast<double>(clips[k].input_bytes);
    }
  const double frames_per_byte = frames > 0 && bytes > 0 ? frames / bytes : 1.0;
  std::vector<double> w(clips.size());
  for (std::size_t k = 0; k < clips.size(); ++k) {
    const bool known = k < probed.size() && probed[k] > 0;
    w[k] = std::max(1.0, known ? static_cast<double>(probed[k]) : static_cast<double>(clips[k].input_bytes) * frames_per_byte);
  }
  return w;
}

std::string format_clip_rate(double clips_per_min) {
  if (!(clips_per_min >= 0) || !std::isfinite(clips_per_min)) return "? clips/min";
  if (clips_per_min < 10) return format("%.1f clips/min", clips_per_min);
  return format("%.0f clips/min", clips_per_min);
}

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
  if (p.clips_per_min >= 0) counts += "  " + format_clip_rate(p.clips_per_min);
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

std::string format_clip_log_line(const ClipResult& c, const BatchProgress& p) {
  return format_clip_line(c, p.done + p.failed, p.total) + "  ETA " +
         (p.remaining() == 0 ? std::string("0s") : format_duration(p.eta_s));
}

}  // namespace rt
