#include "retarget/report/svg_plot.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <utility>

#include "retarget/core/error.hpp"
#include "retarget/core/strings.hpp"

namespace rt::svg {

namespace {

// Layout constants [px]. Text widths are estimated (no font metrics in a file writer): 11 px
// sans-serif averages well under kCharPx per character.
constexpr double kFigureTitlePx = 40;
constexpr double kCharPx = 6.6;
constexpr double kLegendRowPx = 16;
constexpr double kLegendGlyphPx = 26;
constexpr double kPanelTitlePx = 24;
constexpr double kBottomAxisPx = 42;
constexpr double kCoordLimitPx = 1e5;  // far-off points are clamped so numbers stay short
constexpr int kMaxTicks = 100;
constexpr double kDataMargin = 0.04;  // automatic ranges extend this fraction of the data span

bool finite(double v) { return std::isfinite(v); }

// Fixed-decimal, locale-independent number ("-0.00" is written "0.00").
std::string num(double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v + 0.0, std::chars_format::fixed, decimals);
  std::string s(buf, r.ptr);
  if (!s.empty() && s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}
std::string px(double v) { return num(finite(v) ? std::clamp(v, -kCoordLimitPx, kCoordLimitPx) : 0.0, 2); }

// Tick label: fixed decimals, or scientific notation for huge values (keeps labels short).
std::string tick_label(double v, int decimals) {
  if (std::abs(v) < 1e7) return num(v, decimals);
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific, 2);
  return std::string(buf, r.ptr);
}

std::string dash_attr(LineStyle style) {
  switch (style) {
    case LineStyle::Solid: return "";
    case LineStyle::Dashed: return " stroke-dasharray=\"6 4\"";
    case LineStyle::Dotted: return " stroke-dasharray=\"1.5 3\"";
  }
  return "";
}

std::string axis_title(const Axis& a) { return a.unit.empty() ? a.label : a.label + " [" + a.unit + "]"; }

// Decimals that show every tick of `step` exactly (2.5e-k needs one more).
int tick_decimals(double step) {
  int d = static_cast<int>(std::max(0.0, -std::floor(std::log10(step) + 1e-9)));
  const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
  if (std::abs(mantissa - 2.5) < 1e-6) ++d;
  return std::min(d, 12);
}

struct Range {
  double lo = INFINITY, hi = -INFINITY;
  void add(double v) {
    if (!finite(v)) return;
    v = std::clamp(v, -1e300, 1e300);  // keeps spans and margins finite
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return !(lo <= hi); }
};

// A resolved axis: the drawn range and the ticks inside it.
struct Scale {
  double lo = 0, hi = 1;
  std::vector<double> ticks;
  int decimals = 0;
};

Scale make_scale(const Axis& axis, Range data) {
  Scale s;
  if (axis.include_zero && !data.empty()) data.add(0.0);
  if (axis.min < axis.max && finite(axis.min) && finite(axis.max)) {
    s.lo = axis.min;
    s.hi = axis.max;
    const std::vector<double> t = nice_ticks(s.lo, s.hi);
    const double eps = 1e-9 * (s.hi - s.lo);
    for (double v : t)
      if (v >= s.lo - eps && v <= s.hi + eps) s.ticks.push_back(v);
  } else if (data.empty() || data.hi - data.lo <= 1e-12 * std::max(1.0, std::abs(data.lo))) {
    s.ticks = data.empty() ? nice_ticks(0, 1) : nice_ticks(data.lo, data.hi);  // widened around the value
    s.lo = s.ticks.front();
    s.hi = s.ticks.back();
  } else {
    // A margin of kDataMargin of the span on both sides keeps lines off the frame; ticks inside.
    const double pad = kDataMargin * (data.hi - data.lo);
    s.lo = data.lo - pad;
    s.hi = data.hi + pad;
    const double eps = 1e-9 * (s.hi - s.lo);
    for (double v : nice_ticks(data.lo, data.hi))
      if (v >= s.lo - eps && v <= s.hi + eps) s.ticks.push_back(v);
  }
  if (s.ticks.size() >= 2) s.decimals = tick_decimals(s.ticks[1] - s.ticks[0]);
  return s;
}

// Pixel mapping of one panel's plot area.
struct Frame {
  double left, top, width, height;
  Scale x, y;
  double px_x(double v) const { return left + (v - x.lo) / (x.hi - x.lo) * width; }
  double px_y(double v) const { return top + height - (v - y.lo) / (y.hi - y.lo) * height; }
};

struct Point {
  double x, y;
};

// At most 4 points per pixel column (first, lowest, highest, last, in their original order):
// the drawn polyline covers the same pixels as the full one.
std::vector<Point> decimate(const std::vector<Point>& pts, double max_points) {
  if (static_cast<double>(pts.size()) <= max_points) return pts;
  std::vector<Point> out;
  std::size_t i = 0;
  while (i < pts.size()) {
    const double column = std::floor(pts[i].x);
    std::size_t j = i, lo = i, hi = i;
    while (j < pts.size() && std::floor(pts[j].x) == column) {
      if (pts[j].y < pts[lo].y) lo = j;
      if (pts[j].y > pts[hi].y) hi = j;
      ++j;
    }
    std::vector<std::size_t> keep = {i, lo, hi, j - 1};
    std::sort(keep.begin(), keep.end());
    keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
    for (std::size_t k : keep) out.push_back(pts[k]);
    i = j;
  }
  return out;
}

struct BandPoint {
  double x, top, bottom;  // pixels: top is the band's upper edge (smaller y)
};

// Long bands: each pixel column keeps its outer envelope at its first and last x.
std::vector<BandPoint> envelope(const std::vector<BandPoint>& pts) {
  std::vector<BandPoint> out;
  std::size_t i = 0;
  while (i < pts.size()) {
    const double column = std::floor(pts[i].x);
    double top = pts[i].top, bottom = pts[i].bottom;
    std::size_t j = i;
    for (; j < pts.size() && std::floor(pts[j].x) == column; ++j) {
      top = std::min(top, pts[j].top);
      bottom = std::max(bottom, pts[j].bottom);
    }
    out.push_back({pts[i].x, top, bottom});
    if (j - 1 > i) out.push_back({pts[j - 1].x, top, bottom});
    i = j;
  }
  return out;
}

struct LegendEntry {
  enum Kind { Line, Area, Vertical } kind;
  std::string label, color;
  LineStyle style = LineStyle::Solid;
  double opacity = 1;
  double width_px = 1.5;
};

std::vector<LegendEntry> legend_of(const Panel& p) {
  std::vector<LegendEntry> out;
  for (const Series& s : p.series)
    if (!s.name.empty()) out.push_back({LegendEntry::Line, s.name, s.color, s.style, 1.0, s.width_px});
  for (const Band& b : p.bands)
    if (!b.name.empty()) out.push_back({LegendEntry::Area, b.name, b.color, LineStyle::Solid, b.opacity, 0});
  auto seen = [&](const std::string& label, const std::string& color) {
    return std::any_of(out.begin(), out.end(), [&](const LegendEntry& e) { return e.label == label && e.color == color; });
  };
  for (const Span& s : p.spans)
    if (!s.legend.empty() && !seen(s.legend, s.color))
      out.push_back({LegendEntry::Area, s.legend, s.color, LineStyle::Solid, std::max(s.opacity, 0.3), 0});
  for (const Marker& m : p.markers)
    if (!m.legend.empty() && !seen(m.legend, m.color))
      out.push_back({LegendEntry::Vertical, m.legend, m.color, m.style, 1.0, 1.2});
  return out;
}

void check_panel(const Panel& p) {
  RT_DEMAND(p.height_px >= 80 && p.height_px <= 5000, "svg panel height out of range");
  for (const Series& s : p.series) RT_DEMAND(s.x.size() == s.y.size(), "svg series '" + s.name + "': x and y differ in length");
  for (const Band& b : p.bands)
    RT_DEMAND(b.x.size() == b.lo.size() && b.x.size() == b.hi.size(), "svg band '" + b.name + "': x, lo and hi differ in length");
  for (const TimelineRow& r : p.rows) RT_DEMAND(r.t.size() == r.on.size(), "svg timeline row '" + r.label + "': t and on differ in length");
  RT_DEMAND(p.rows.empty() || (p.series.empty() && p.bands.empty()), "svg timeline panel with series or bands");
}

class Writer {
 public:
  explicit Writer(const Figure& f) : fig_(f) {}

  std::string run() {
    RT_DEMAND(fig_.width_px >= 200 && fig_.width_px <= 10000, "svg figure width out of range");
    for (const Panel& p : fig_.panels) check_panel(p);
    layout_margins();
    double height = kFigureTitlePx;
    for (const Panel& p : fig_.panels) height += p.height_px;
    const std::string w = std::to_string(fig_.width_px), h = num(height, 0);
    out_ += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out_ += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h + "\" viewBox=\"0 0 " + w + " " + h +
            "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    out_ += "<rect x=\"0\" y=\"0\" width=\"" + w + "\" height=\"" + h + "\" fill=\"#ffffff\"/>\n";
    if (!fig_.title.empty())
      out_ += "<text x=\"" + px(fig_.width_px / 2.0) + "\" y=\"25\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">" +
              escape_xml(fig_.title) + "</text>\n";
    double top = kFigureTitlePx;
    for (std::size_t i = 0; i < fig_.panels.size(); ++i) {
      panel(fig_.panels[i], static_cast<int>(i), top);
      top += fig_.panels[i].height_px;
    }
    out_ += "</svg>\n";
    return std::move(out_);
  }

 private:
  // One left margin (tick or row labels) and one legend column for the whole figure, so the
  // panels' time axes line up.
  void layout_margins() {
    std::size_t label_chars = 6, legend_chars = 0;
    for (const Panel& p : fig_.panels) {
      for (const TimelineRow& r : p.rows) label_chars = std::max(label_chars, r.label.size());
      for (const LegendEntry& e : legend_of(p)) legend_chars = std::max(legend_chars, e.label.size());
    }
    left_ = std::clamp(30 + kCharPx * static_cast<double>(label_chars), 70.0, 240.0);
    right_ = legend_chars == 0 ? 20.0 : std::clamp(kLegendGlyphPx + 26 + kCharPx * static_cast<double>(legend_chars), 80.0, 320.0);
    right_ = std::min(right_, std::max(20.0, fig_.width_px - left_ - 100.0));
  }

  void panel(const Panel& p, int index, double top) {
    Frame f;
    f.left = left_;
    f.top = top + (p.title.empty() ? 10 : kPanelTitlePx + 4);
    f.width = std::max(10.0, fig_.width_px - left_ - right_);
    f.height = std::max(10.0, top + p.height_px - kBottomAxisPx - f.top);
    Range xr, yr;
    for (const Series& s : p.series) {
      for (double v : s.x) xr.add(v);
      for (double v : s.y) yr.add(v);
    }
    for (const Band& b : p.bands) {
      for (double v : b.x) xr.add(v);
      for (std::size_t i = 0; i < b.x.size(); ++i)
        if (finite(b.lo[i]) && finite(b.hi[i])) {
          yr.add(b.lo[i]);
          yr.add(b.hi[i]);
        }
    }
    for (const TimelineRow& r : p.rows)
      for (double v : r.t) xr.add(v);
    for (const Span& s : p.spans) {
      xr.add(s.x0);
      xr.add(s.x1);
    }
    for (const Marker& m : p.markers) xr.add(m.x);
    f.x = make_scale(p.x, xr);
    const bool timeline = !p.rows.empty();
    if (timeline) {
      f.y.lo = 0;
      f.y.hi = static_cast<double>(p.rows.size());
    } else {
      f.y = make_scale(p.y, yr);
    }

    const std::string id = "plot" + std::to_string(index);
    out_ += "<g id=\"panel" + std::to_string(index) + "\">\n";
    if (!p.title.empty())
      out_ += "<text x=\"" + px(f.left) + "\" y=\"" + px(top + 18) + "\" font-size=\"13\" font-weight=\"bold\">" +
              escape_xml(p.title) + "</text>\n";
    out_ += "<clipPath id=\"" + id + "\"><rect x=\"" + px(f.left) + "\" y=\"" + px(f.top) + "\" width=\"" + px(f.width) +
            "\" height=\"" + px(f.height) + "\"/></clipPath>\n";
    grid_and_axes(p, f, timeline);
    out_ += "<g clip-path=\"url(#" + id + ")\">\n";
    for (const Band& b : p.bands) band(b, f);
    for (const Span& s : p.spans) span(s, f);
    for (std::size_t r = 0; r < p.rows.size(); ++r) timeline_row(p.rows[r], r, f);
    for (const Series& s : p.series) series(s, f);
    for (const Marker& m : p.markers) marker(m, f);
    out_ += "</g>\n";
    out_ += "<rect x=\"" + px(f.left) + "\" y=\"" + px(f.top) + "\" width=\"" + px(f.width) + "\" height=\"" + px(f.height) +
            "\" fill=\"none\" stroke=\"#444444\"/>\n";
    legend(p, f);
    out_ += "</g>\n";
  }

  void grid_and_axes(const Panel& p, const Frame& f, bool timeline) {
    const double bottom = f.top + f.height;
    for (double t : f.x.ticks) {
      const std::string x = px(f.px_x(t));
      out_ += "<line x1=\"" + x + "\" y1=\"" + px(f.top) + "\" x2=\"" + x + "\" y2=\"" + px(bottom) +
              "\" stroke=\"#e6e6e6\"/>\n";
      out_ += "<text x=\"" + x + "\" y=\"" + px(bottom + 14) + "\" text-anchor=\"middle\">" + tick_label(t, f.x.decimals) + "</text>\n";
    }
    out_ += "<text x=\"" + px(f.left + f.width / 2) + "\" y=\"" + px(bottom + 32) + "\" text-anchor=\"middle\">" +
            escape_xml(axis_title(p.x)) + "</text>\n";
    if (timeline) {
      for (std::size_t r = 0; r < p.rows.size(); ++r) {
        const double y_mid = f.top + (static_cast<double>(r) + 0.5) * f.height / static_cast<double>(p.rows.size());
        out_ += "<text x=\"" + px(f.left - 6) + "\" y=\"" + px(y_mid + 4) + "\" text-anchor=\"end\">" +
                escape_xml(p.rows[r].label) + "</text>\n";
        if (r > 0) {
          const std::string y = px(f.top + static_cast<double>(r) * f.height / static_cast<double>(p.rows.size()));
          out_ += "<line x1=\"" + px(f.left) + "\" y1=\"" + y + "\" x2=\"" + px(f.left + f.width) + "\" y2=\"" + y +
                  "\" stroke=\"#e6e6e6\"/>\n";
        }
      }
      return;
    }
    for (double t : f.y.ticks) {
      const std::string y = px(f.px_y(t));
      out_ += "<line x1=\"" + px(f.left) + "\" y1=\"" + y + "\" x2=\"" + px(f.left + f.width) + "\" y2=\"" + y +
              "\" stroke=\"#e6e6e6\"/>\n";
      out_ += "<text x=\"" + px(f.left - 6) + "\" y=\"" + px(f.px_y(t) + 4) + "\" text-anchor=\"end\">" + tick_label(t, f.y.decimals) +
              "</text>\n";
    }
    const std::string cx = px(14), cy = px(f.top + f.height / 2);
    out_ += "<text x=\"" + cx + "\" y=\"" + cy + "\" text-anchor=\"middle\" transform=\"rotate(-90 " + cx + " " + cy + ")\">" +
            escape_xml(axis_title(p.y)) + "</text>\n";
  }

  void band(const Band& b, const Frame& f) {
    std::string d;
    std::size_t i = 0;
    const std::size_t n = b.x.size();
    auto ok = [&](std::size_t k) { return finite(b.x[k]) && finite(b.lo[k]) && finite(b.hi[k]); };
    while (i < n) {
      if (!ok(i)) {
        ++i;
        continue;
      }
      std::vector<BandPoint> run;  // one run of finite samples, in pixels (top = hi, bottom = lo)
      for (; i < n && ok(i); ++i) run.push_back({f.px_x(b.x[i]), f.px_y(b.hi[i]), f.px_y(b.lo[i])});
      if (static_cast<double>(run.size()) > 2 * f.width) run = envelope(run);
      if (run.size() == 1) {  // a lone sample: half a pixel either side, so it stays visible
        run = {run[0], run[0]};
        run[0].x -= 0.5;
        run[1].x += 0.5;
      }
      d += (d.empty() ? "M" : " M") + px(run[0].x) + " " + px(run[0].top);
      for (std::size_t k = 1; k < run.size(); ++k) d += " L" + px(run[k].x) + " " + px(run[k].top);
      for (std::size_t k = run.size(); k-- > 0;) d += " L" + px(run[k].x) + " " + px(run[k].bottom);
      d += " Z";
    }
    if (d.empty()) return;
    out_ += "<path d=\"" + d + "\" fill=\"" + escape_xml(b.color) + "\" fill-opacity=\"" + num(b.opacity, 3) + "\" stroke=\"none\">";
    if (!b.name.empty()) out_ += "<title>" + escape_xml(b.name) + "</title>";
    out_ += "</path>\n";
  }

  void span(const Span& s, const Frame& f) {
    if (!finite(s.x0) || !finite(s.x1)) return;
    double x0 = f.px_x(std::min(s.x0, s.x1)), x1 = f.px_x(std::max(s.x0, s.x1));
    if (x1 - x0 < 1) {
      const double c = 0.5 * (x0 + x1);
      x0 = c - 0.5;
      x1 = c + 0.5;
    }
    x0 = std::max(x0, f.left - 1);
    x1 = std::min(x1, f.left + f.width + 1);
    if (x1 <= x0) return;
    out_ += "<rect x=\"" + px(x0) + "\" y=\"" + px(f.top) + "\" width=\"" + px(x1 - x0) + "\" height=\"" + px(f.height) +
            "\" fill=\"" + escape_xml(s.color) + "\" fill-opacity=\"" + num(s.opacity, 3) + "\">";
    if (!s.tooltip.empty()) out_ += "<title>" + escape_xml(s.tooltip) + "</title>";
    out_ += "</rect>\n";
  }

  void timeline_row(const TimelineRow& r, std::size_t index, const Frame& f) {
    const std::size_t n = r.t.size();
    if (n == 0) return;
    // The last sample lasts one median sample period.
    std::vector<double> dts;
    for (std::size_t i = 1; i < n; ++i)
      if (finite(r.t[i]) && finite(r.t[i - 1])) dts.push_back(r.t[i] - r.t[i - 1]);
    double last_dt = 0;
    if (!dts.empty()) {
      std::nth_element(dts.begin(), dts.begin() + static_cast<std::ptrdiff_t>(dts.size() / 2), dts.end());
      last_dt = dts[dts.size() / 2];
    }
    const double row_h = f.height / (f.y.hi - f.y.lo);
    const double y = f.top + (static_cast<double>(index) + 0.2) * row_h, h = 0.6 * row_h;
    std::string rects;
    std::size_t i = 0;
    while (i < n) {
      if (!r.on[i] || !finite(r.t[i])) {
        ++i;
        continue;
      }
      const double t0 = r.t[i];
      while (i < n && r.on[i] && finite(r.t[i])) ++i;
      const double t1 = i < n ? r.t[i] : r.t[n - 1] + last_dt;
      const double x0 = f.px_x(t0), x1 = std::max(f.px_x(t1), x0 + 1);
      rects += "<rect x=\"" + px(x0) + "\" y=\"" + px(y) + "\" width=\"" + px(x1 - x0) + "\" height=\"" + px(h) + "\"/>\n";
    }
    if (rects.empty()) return;
    out_ += "<g fill=\"" + escape_xml(r.color) + "\" fill-opacity=\"" + num(r.opacity, 3) + "\">\n" + rects + "</g>\n";
  }

  void series(const Series& s, const Frame& f) {
    const std::size_t n = s.x.size();
    std::string d;
    std::size_t i = 0;
    while (i < n) {
      if (!finite(s.x[i]) || !finite(s.y[i])) {
        ++i;
        continue;
      }
      std::vector<Point> pts;
      for (; i < n && finite(s.x[i]) && finite(s.y[i]); ++i) {
        if (s.step && !pts.empty()) pts.push_back({f.px_x(s.x[i]), pts.back().y});
        pts.push_back({f.px_x(s.x[i]), f.px_y(s.y[i])});
      }
      // A step value holds until the next sample's time even when that sample is a gap.
      if (s.step && i < n && finite(s.x[i])) pts.push_back({f.px_x(s.x[i]), pts.back().y});
      if (!s.step) pts = decimate(pts, 4 * f.width);
      d += (d.empty() ? "M" : " M") + px(pts[0].x) + " " + px(pts[0].y);
      if (pts.size() == 1) d += " l0 0";  // a lone sample: a dot (round caps)
      for (std::size_t k = 1; k < pts.size(); ++k) d += " L" + px(pts[k].x) + " " + px(pts[k].y);
    }
    if (d.empty()) return;
    out_ += "<path d=\"" + d + "\" fill=\"none\" stroke=\"" + escape_xml(s.color) + "\" stroke-width=\"" + num(s.width_px, 2) +
            "\" stroke-linejoin=\"round\" stroke-linecap=\"round\"" + dash_attr(s.style) + ">";
    if (!s.name.empty()) out_ += "<title>" + escape_xml(s.name) + "</title>";
    out_ += "</path>\n";
  }

  void marker(const Marker& m, const Frame& f) {
    if (!finite(m.x)) return;
    const std::string x = px(f.px_x(m.x));
    out_ += "<line x1=\"" + x + "\" y1=\"" + px(f.top) + "\" x2=\"" + x + "\" y2=\"" + px(f.top + f.height) + "\" stroke=\"" +
            escape_xml(m.color) + "\" stroke-width=\"1.2\"" + dash_attr(m.style) + ">";
    if (!m.tooltip.empty()) out_ += "<title>" + escape_xml(m.tooltip) + "</title>";
    out_ += "</line>\n";
  }

  void legend(const Panel& p, const Frame& f) {
    const std::vector<LegendEntry> entries = legend_of(p);
    if (entries.empty()) return;
    const double x = f.left + f.width + 12;
    const std::size_t fit = static_cast<std::size_t>(std::max(1.0, std::floor(f.height / kLegendRowPx)));
    for (std::size_t i = 0; i < entries.size(); ++i) {
      const double y = f.top + 8 + static_cast<double>(i) * kLegendRowPx;
      if (i + 1 == fit && entries.size() > fit) {
        out_ += "<text x=\"" + px(x) + "\" y=\"" + px(y + 4) + "\">… " + std::to_string(entries.size() - i) + " more</text>\n";
        break;
      }
      const LegendEntry& e = entries[i];
      const std::string color = escape_xml(e.color);
      switch (e.kind) {
        case LegendEntry::Line:
          out_ += "<line x1=\"" + px(x) + "\" y1=\"" + px(y) + "\" x2=\"" + px(x + kLegendGlyphPx - 4) + "\" y2=\"" + px(y) +
                  "\" stroke=\"" + color + "\" stroke-width=\"" + num(e.width_px, 2) + "\"" + dash_attr(e.style) + "/>\n";
          break;
        case LegendEntry::Area:
          out_ += "<rect x=\"" + px(x) + "\" y=\"" + px(y - 5) + "\" width=\"" + px(kLegendGlyphPx - 4) +
                  "\" height=\"10\" fill=\"" + color + "\" fill-opacity=\"" + num(e.opacity, 3) + "\"/>\n";
          break;
        case LegendEntry::Vertical: {
          const std::string mx = px(x + (kLegendGlyphPx - 4) / 2);
          out_ += "<line x1=\"" + mx + "\" y1=\"" + px(y - 6) + "\" x2=\"" + mx + "\" y2=\"" + px(y + 6) + "\" stroke=\"" + color +
                  "\" stroke-width=\"1.2\"" + dash_attr(e.style) + "/>\n";
          break;
        }
      }
      out_ += "<text x=\"" + px(x + kLegendGlyphPx + 2) + "\" y=\"" + px(y + 4) + "\">" + escape_xml(e.label) + "</text>\n";
    }
  }

  const Figure& fig_;
  std::string out_;
  double left_ = 70, right_ = 20;
};

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int target_count) {
  RT_DEMAND(finite(lo) && finite(hi), "nice_ticks of a non-finite range");
  if (lo > hi) std::swap(lo, hi);
  lo = std::max(lo, -1e300);  // keeps hi - lo and the step finite
  hi = std::min(hi, 1e300);
  if (hi - lo <= 1e-12 * std::max(1.0, std::abs(lo))) {
    const double pad = lo == 0 ? 1.0 : 0.1 * std::abs(lo);
    lo -= pad;
    hi += pad;
  }
  const double raw = (hi - lo) / std::max(1, target_count - 1);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  const double step = (norm <= 1 ? 1 : norm <= 2 ? 2 : norm <= 2.5 ? 2.5 : norm <= 5 ? 5 : 10) * mag;
  const double first = std::floor(lo / step + 1e-9), last = std::ceil(hi / step - 1e-9);
  const int count = static_cast<int>(std::min<double>(last - first, kMaxTicks));
  std::vector<double> ticks;
  for (int i = 0; i <= count; ++i) {
    double v = (first + i) * step;
    if (std::abs(v) < 1e-9 * step) v = 0;
    ticks.push_back(v);
  }
  return ticks;
}

std::string escape_xml(const std::string& text) {
  static constexpr const char* kReplacement = "\xEF\xBF\xBD";  // U+FFFD
  std::string out;
  out.reserve(text.size());
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  std::size_t i = 0;
  while (i < n) {
    const unsigned char c = s[i];
    if (c < 0x80) {
      switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        default:
          if (c < 0x20 && c != '\t' && c != '\n' && c != '\r') out += kReplacement;  // not allowed in XML 1.0
          else out.push_back(static_cast<char>(c));
      }
      ++i;
      continue;
    }
    // Multi-byte UTF-8: accept only well-formed, shortest-form scalar values that XML allows
    // (not the noncharacters U+FFFE and U+FFFF, EF BF BE and EF BF BF).
    const std::size_t len = utf8_sequence_length(text, i);
    const bool ok = len > 0 && !(len == 3 && c == 0xEF && s[i + 1] == 0xBF && (s[i + 2] == 0xBE || s[i + 2] == 0xBF));
    if (ok) {
      out.append(text, i, len);
      i += len;
    } else {
      out += kReplacement;
      ++i;
    }
  }
  return out;
}

std::string render(const Figure& figure) { return Writer(figure).run(); }

}  // namespace rt::svg
