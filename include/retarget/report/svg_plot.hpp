#pragma once
/// A small SVG plotting module for reports (design.md §5 "Report"): time-series line plots with
/// named series, shaded bands that vary over time, vertical markers and shaded spans, and boolean
/// timelines, stacked as panels of a fixed-size figure. No plotting library exists in Debian; this
/// covers exactly what the reports need.
///
/// Conventions
/// - Data coordinates are plain doubles; a NaN (or infinite) value in a series or band breaks the
///   line or area there (a gap), it is never drawn as zero.
/// - Output is deterministic: the same Figure gives the same bytes (numbers are written with a
///   fixed number of decimals by std::to_chars, independent of the C locale).
/// - All text (titles, labels, legend entries, tooltips) is XML-escaped; control characters and
///   invalid UTF-8 bytes are replaced, so any string can be passed in.
/// - Long series are reduced to at most 4 points per horizontal pixel (first, min, max, last of
///   each pixel column), which keeps the file small without changing what is drawn.

#include <string>
#include <vector>

namespace rt::svg {

enum class LineStyle { Solid, Dashed, Dotted };

/// A line through (x[i], y[i]). x must be non-decreasing (time); NaN in x or y breaks the line.
struct Series {
  std::string name;           ///< legend entry ("" = not in the legend)
  std::vector<double> x, y;   ///< same length
  std::string color = "#1f77b4";
  LineStyle style = LineStyle::Solid;
  double width_px = 1.5;
  bool step = false;          ///< hold each value until the next sample (staircase) instead of interpolating
};

/// A filled area between lo[i] and hi[i] over x[i] (e.g. the support polygon's extent along one
/// axis over time). A sample where lo or hi is NaN is a gap: the area ends before it.
struct Band {
  std::string name;           ///< legend entry ("" = not in the legend)
  std::vector<double> x, lo, hi;  ///< same length
  std::string color = "#2ca02c";
  double opacity = 0.25;
};

/// A translucent rectangle over the x-range [x0, x1] at full panel height (e.g. a violation's
/// time span). Drawn at least 1 px wide so instantaneous events stay visible.
struct Span {
  double x0 = 0, x1 = 0;
  std::string color = "#d62728";
  double opacity = 0.15;
  std::string legend;         ///< legend entry; spans with the same legend and colour share one entry
  std::string tooltip;        ///< shown on hover (<title>), e.g. the violation's detail
};

/// A vertical line at x (e.g. a re-planning activation).
struct Marker {
  double x = 0;
  std::string color = "#9467bd";
  LineStyle style = LineStyle::Dashed;
  std::string legend;         ///< legend entry; markers with the same legend and colour share one entry
  std::string tooltip;
};

/// One row of a boolean timeline: a horizontal bar wherever `on` holds. Sample i covers
/// [t[i], t[i+1]); the last sample covers one median sample period.
struct TimelineRow {
  std::string label;          ///< written left of the row
  std::vector<double> t;
  std::vector<bool> on;       ///< same length as t
  std::string color = "#1f77b4";
  double opacity = 1.0;
};

struct Axis {
  std::string label;          ///< e.g. "time"
  std::string unit;           ///< e.g. "s"; the axis title reads "time [s]"
  /// Fixed range; when min >= max (the default) the range is the data's, extended by 4 % of its
  /// span on both sides, with "nice" ticks (1, 2, 2.5, 5 × 10^k) inside it.
  double min = 0, max = 0;
  /// Automatic ranges include 0 (errors, forces: keeps small variations from looking large).
  bool include_zero = false;
};

/// One plot area with its own axes. A panel with timeline rows is a timeline: its y axis lists
/// the row labels, and it must not also hold series or bands.
struct Panel {
  std::string title;
  Axis x{"time", "s"};
  Axis y;
  int height_px = 300;        ///< plot area plus its axes and title
  std::vector<Band> bands;    ///< drawn first (background)
  std::vector<Span> spans;
  std::vector<Series> series;
  std::vector<Marker> markers;  ///< drawn last (foreground)
  std::vector<TimelineRow> rows;
};

/// Panels stacked top to bottom under a title; the legend of each panel sits to its right.
struct Figure {
  std::string title;
  int width_px = 960;
  std::vector<Panel> panels;
};

/// The SVG document (UTF-8, with an XML declaration). Total height: 40 px for the title plus each
/// panel's height_px. Throws InternalError for inconsistent input (series lengths differ, a
/// timeline panel with series, sizes out of range).
std::string render(const Figure& figure);

/// "Nice" tick values covering [lo, hi] with about `target_count` ticks (steps of 1, 2, 2.5 or
/// 5 × 10^k); the first tick is <= lo and the last >= hi. lo == hi is widened first.
std::vector<double> nice_ticks(double lo, double hi, int target_count = 6);

/// XML text/attribute escaping (& < > " ' ), with control characters and invalid UTF-8 bytes
/// replaced by U+FFFD.
std::string escape_xml(const std::string& text);

}  // namespace rt::svg
