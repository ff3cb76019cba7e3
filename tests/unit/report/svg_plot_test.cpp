#include "retarget/report/svg_plot.hpp"

#include <gtest/gtest.h>

#include <clocale>
#include <cmath>
#include <limits>

#include "retarget/core/error.hpp"
#include "xml_check.hpp"

namespace rt::svg {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Number of subpaths ("M" commands) in a path's d attribute.
std::size_t subpaths(const std::string& d) {
  std::size_t n = 0;
  for (char c : d) n += c == 'M';
  return n;
}

// The element whose <title> child reads `title` is the one just before that title element.
const test::XmlElement* titled(const test::XmlCheck& x, const std::string& name, const std::string& title) {
  for (std::size_t i = 1; i < x.elements.size(); ++i)
    if (x.elements[i].name == "title" && x.elements[i].text == title && x.elements[i - 1].name == name) return &x.elements[i - 1];
  return nullptr;
}

// A 400 x 240 figure whose plot area is known exactly: left margin 70 px (minimum), legend column
// 80 px (minimum), panel top 40 + 10 px, height 200 - 10 - 42 = 148 px.
Figure small_figure() {
  Figure f;
  f.width_px = 400;
  Panel p;
  p.height_px = 200;
  p.x = {"time", "s", 0, 10};
  p.y = {"y", "m", 0, 1};
  Series s;
  s.name = "s";
  s.x = {0, 5, 10};
  s.y = {0, 0.5, 1};
  p.series.push_back(s);
  f.panels.push_back(p);
  return f;
}

Figure full_figure() {
  Figure f;
  f.title = "COM & COP <y>";
  Panel p;
  p.title = "panel \"one\"";
  p.y = {"y", "m"};
  Band b;
  b.name = "support";
  b.x = {0, 1, 2, 3, 4, 5};
  b.lo = {-0.1, -0.1, kNaN, -0.05, -0.05, -0.05};
  b.hi = {0.1, 0.1, kNaN, 0.12, 0.12, 0.12};
  p.bands.push_back(b);
  Series com;
  com.name = "COM";
  com.x = {0, 1, 2, 3, 4, 5};
  com.y = {0, 0.01, 0.02, kNaN, 0.03, 0.02};
  p.series.push_back(com);
  Series cop = com;
  cop.name = "COP";
  cop.color = "#d62728";
  cop.style = LineStyle::Dashed;
  p.series.push_back(cop);
  p.spans.push_back({1.0, 1.5, "#d62728", 0.15, "cop-near-edge", "COP 0.004 m inside"});
  p.spans.push_back({2.0, 2.0, "#d62728", 0.15, "cop-near-edge", "instantaneous"});
  p.markers.push_back({0.5, "#9467bd", LineStyle::Dashed, "re-plan", "case 1"});
  f.panels.push_back(p);
  Panel t;
  t.title = "contacts";
  TimelineRow row;
  row.label = "left actual";
  row.t = {0, 1, 2, 3, 4};
  row.on = {true, true, false, false, true};
  t.rows.push_back(row);
  row.label = "right actual";
  row.on = {false, true, true, true, true};
  t.rows.push_back(row);
  f.panels.push_back(t);
  return f;
}

TEST(SvgPlot, FullFigureIsWellFormedWithTheExpectedElements) {
  const std::string svg = render(full_figure());
  const test::XmlCheck x = test::check_xml(svg);
  ASSERT_TRUE(x.ok) << x.error;
  ASSERT_FALSE(x.elements.empty());
  EXPECT_EQ(x.elements.front().name, "svg");
  EXPECT_EQ(x.elements.front().attributes.at("width"), "960");
  EXPECT_EQ(x.elements.front().attributes.at("height"), "640");  // 40 + 2 x 300
  EXPECT_EQ(x.count("clipPath"), 2u);
  EXPECT_NE(titled(x, "path", "COM"), nullptr);
  EXPECT_NE(titled(x, "path", "support"), nullptr);
  EXPECT_NE(titled(x, "line", "case 1"), nullptr);
  const test::XmlElement* span = titled(x, "rect", "instantaneous");
  ASSERT_NE(span, nullptr);
  EXPECT_EQ(span->attributes.at("width"), "1.00");  // zero-length spans stay visible
  // Dashed style, escaped titles and axis labels with units.
  EXPECT_EQ(titled(x, "path", "COP")->attributes.at("stroke-dasharray"), "6 4");
  EXPECT_NE(svg.find("COM &amp; COP &lt;y&gt;"), std::string::npos);
  EXPECT_NE(svg.find("panel &quot;one&quot;"), std::string::npos);
  EXPECT_NE(svg.find(">y [m]</text>"), std::string::npos);
  EXPECT_NE(svg.find(">time [s]</text>"), std::string::npos);
  EXPECT_NE(svg.find(">left actual</text>"), std::string::npos);
  // One legend entry per distinct span legend: "cop-near-edge" appears once as legend text.
  std::size_t legend_texts = 0;
  for (const auto& e : x.elements) legend_texts += e.name == "text" && e.text == "cop-near-edge";
  EXPECT_EQ(legend_texts, 1u);
}

TEST(SvgPlot, ExactCoordinatesOfASmallPlot) {
  const std::string svg = render(small_figure());
  const test::XmlCheck x = test::check_xml(svg);
  ASSERT_TRUE(x.ok) << x.error;
  const test::XmlElement* path = titled(x, "path", "s");
  ASSERT_NE(path, nullptr);
  EXPECT_EQ(path->attributes.at("d"), "M70.00 198.00 L195.00 124.00 L320.00 50.00");
  const test::XmlElement* clip = nullptr;
  for (const auto& e : x.elements)
    if (e.name == "rect" && e.attributes.count("x") && e.attributes.at("x") == "70.00" && e.attributes.count("fill") == 0) clip = &e;
  ASSERT_NE(clip, nullptr);
  EXPECT_EQ(clip->attributes.at("width"), "250.00");
  EXPECT_EQ(clip->attributes.at("height"), "148.00");
  // Ticks of the fixed range [0, 10]: 0, 2, ..., 10 without decimals; y: 0.0, 0.2, ... 1.0.
  EXPECT_NE(svg.find(">10</text>"), std::string::npos);
  EXPECT_NE(svg.find(">0.2</text>"), std::string::npos);
}

TEST(SvgPlot, OutputIsDeterministicAndLocaleIndependent) {
  const std::string a = render(full_figure());
  EXPECT_EQ(a, render(full_figure()));
  // A comma-decimal locale must not change the numbers (std::to_chars ignores the locale).
  const std::string old = std::setlocale(LC_NUMERIC, nullptr);
  bool switched = false;
  for (const char* name : {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "fr_FR.utf8"})
    if (std::setlocale(LC_NUMERIC, name)) {
      switched = true;
      break;
    }
  const std::string b = render(full_figure());
  std::setlocale(LC_NUMERIC, old.c_str());
  EXPECT_EQ(a, b);
  if (!switched) std::cout << "(no comma-decimal locale installed; locale part checked against C only)\n";
}

TEST(SvgPlot, NanBreaksLinesAndBands) {
  const test::XmlCheck x = test::check_xml(render(full_figure()));
  ASSERT_TRUE(x.ok) << x.error;
  const std::string com = titled(x, "path", "COM")->attributes.at("d");
  EXPECT_EQ(subpaths(com), 2u) << com;
  EXPECT_EQ(com.find("nan"), std::string::npos);
  const std::string band = titled(x, "path", "support")->attributes.at("d");
  EXPECT_EQ(subpaths(band), 2u) << band;
  EXPECT_EQ(std::count(band.begin(), band.end(), 'Z'), 2);

  // A lone finite sample between gaps is a dot, and an all-NaN series draws nothing.
  Figure f = small_figure();
  f.panels[0].series[0].y = {kNaN, 0.5, kNaN};
  Series empty;
  empty.name = "e";  // one character, like "s": the legend column keeps its width
  empty.x = {0, 1};
  empty.y = {kNaN, kNaN};
  f.panels[0].series.push_back(empty);
  const test::XmlCheck y = test::check_xml(render(f));
  ASSERT_TRUE(y.ok) << y.error;
  EXPECT_EQ(titled(y, "path", "s")->attributes.at("d"), "M195.00 124.00 l0 0");
  EXPECT_EQ(titled(y, "path", "e"), nullptr);
}

TEST(SvgPlot, StepSeriesHoldsValuesUntilTheNextSample) {
  Figure f = small_figure();
  Series& s = f.panels[0].series[0];
  s.step = true;
  s.x = {0, 5, 10};
  s.y = {0, 1, kNaN};
  const test::XmlCheck x = test::check_xml(render(f));
  ASSERT_TRUE(x.ok) << x.error;
  // 0 until t = 5, then 1 until t = 10 (the next sample's time, although its value is a gap).
  EXPECT_EQ(titled(x, "path", "s")->attributes.at("d"), "M70.00 198.00 L195.00 198.00 L195.00 50.00 L320.00 50.00");
}

TEST(SvgPlot, TimelineBarsCoverTheirSamples) {
  Figure f;
  f.width_px = 400;
  Panel p;
  p.height_px = 200;
  p.x = {"time", "s", 0, 10};
  TimelineRow r;
  r.label = "left";
  r.t = {0, 1, 2, 3, 4};
  r.on = {true, true, false, false, true};
  r.color = "#123456";
  p.rows.push_back(r);
  f.panels.push_back(p);
  const std::string svg = render(f);
  const test::XmlCheck x = test::check_xml(svg);
  ASSERT_TRUE(x.ok) << x.error;
  // No legend: plot area 70 .. 380 (310 px for 10 s). Bars [0, 2) s and [4, 5) s (the last sample
  // lasts the median period, 1 s).
  std::vector<std::string> widths;
  bool in_row_group = false;
  for (const auto& e : x.elements) {
    if (e.name == "g") in_row_group = e.attributes.count("fill") && e.attributes.at("fill") == "#123456";
    if (in_row_group && e.name == "rect" && e.attributes.count("fill") == 0) widths.push_back(e.attributes.at("x") + "+" + e.attributes.at("width"));
  }
  ASSERT_EQ(widths.size(), 2u);
  EXPECT_EQ(widths[0], "70.00+62.00");
  EXPECT_EQ(widths[1], "194.00+31.00");
}

TEST(SvgPlot, LongSeriesAreReducedPerPixelColumnKeepingExtremes) {
  Figure f = small_figure();
  Series& s = f.panels[0].series[0];
  s.x.clear();
  s.y.clear();
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    s.x.push_back(10.0 * i / (n - 1));
    s.y.push_back(i == n / 2 ? 1.0 : 0.25 + 0.1 * std::sin(i * 0.01));  // one spike to the top
  }
  const std::string svg = render(f);
  const test::XmlCheck x = test::check_xml(svg);
  ASSERT_TRUE(x.ok) << x.error;
  const std::string d = titled(x, "path", "s")->attributes.at("d");
  const std::size_t points = static_cast<std::size_t>(std::count(d.begin(), d.end(), 'L')) + 1;
  EXPECT_LE(points, 4u * 251u);
  EXPECT_GT(points, 250u);
  EXPECT_NE(d.find(" 50.00"), std::string::npos) << "the spike to y = 1 (pixel 50) was lost";
  EXPECT_LT(svg.size(), 40000u);
}

TEST(SvgPlot, NiceTicks) {
  const std::vector<double> a = nice_ticks(0, 1);
  ASSERT_EQ(a.size(), 6u);
  EXPECT_DOUBLE_EQ(a[1], 0.2);
  EXPECT_DOUBLE_EQ(a.back(), 1.0);
  const std::vector<double> b = nice_ticks(-0.037, 0.081);
  ASSERT_GE(b.size(), 3u);
  EXPECT_LE(b.front(), -0.037);
  EXPECT_GE(b.back(), 0.081);
  EXPECT_NEAR(b[1] - b[0], 0.025, 1e-12);
  EXPECT_EQ(std::count(b.begin(), b.end(), 0.0), 1);  // zero is exactly zero
  const std::vector<double> c = nice_ticks(5, 5);  // degenerate range is widened
  EXPECT_LT(c.front(), 5);
  EXPECT_GT(c.back(), 5);
  const std::vector<double> d = nice_ticks(0, 0);
  EXPECT_LE(d.front(), -1);
  EXPECT_GE(d.back(), 1);
  EXPECT_LE(nice_ticks(-1e9, 1e9).size(), 12u);
  EXPECT_LE(nice_ticks(-1.7e308, 1.7e308).size(), 12u);
  EXPECT_THROW(nice_ticks(0, kNaN), InternalError);

  // Extreme data still renders a well-formed file with short numbers.
  Figure f = small_figure();
  f.panels[0].y = {"y", "m"};
  f.panels[0].series[0].y = {-1.7e308, 0, 1.7e308};
  const std::string svg = render(f);
  EXPECT_TRUE(test::check_xml(svg).ok);
  EXPECT_LT(svg.size(), 6000u);
}

TEST(SvgPlot, EscapesTextAndRepairsBadBytes) {
  EXPECT_EQ(escape_xml("a<b & \"c\" 'd' >"), "a&lt;b &amp; &quot;c&quot; &apos;d&apos; &gt;");
  EXPECT_EQ(escape_xml("ok \xC3\xA9 \xE2\x86\x90"), "ok \xC3\xA9 \xE2\x86\x90");   // é and ← stay
  EXPECT_EQ(escape_xml("x\x01y"), "x\xEF\xBF\xBDy");                            // control character
  EXPECT_EQ(escape_xml("\xFF"), "\xEF\xBF\xBD");                                // not UTF-8
  EXPECT_EQ(escape_xml("\xC0\xAF"), "\xEF\xBF\xBD\xEF\xBF\xBD");                // overlong '/'
  EXPECT_EQ(escape_xml("\xED\xA0\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");  // surrogate
  EXPECT_EQ(escape_xml("\xE2\x86"), "\xEF\xBF\xBD\xEF\xBF\xBD");                // truncated
  EXPECT_EQ(escape_xml("tab\tnl\n"), "tab\tnl\n");

  Figure f = full_figure();
  f.title = "<script>alert('x')</script> & \x02\xFE";
  f.panels[0].series[0].name = "]]><evil attr=\"";
  const test::XmlCheck x = test::check_xml(render(f));
  EXPECT_TRUE(x.ok) << x.error;
  for (const auto& e : x.elements) EXPECT_NE(e.name, "script");
}

TEST(SvgPlot, InconsistentInputIsAnInternalError) {
  Figure f = small_figure();
  f.panels[0].series[0].y.pop_back();
  EXPECT_THROW(render(f), InternalError);
  Figure g = full_figure();
  g.panels[1].series.push_back(g.panels[0].series[0]);  // a timeline with a series
  EXPECT_THROW(render(g), InternalError);
  Figure h = small_figure();
  h.width_px = 10;
  EXPECT_THROW(render(h), InternalError);
}

TEST(SvgPlot, EmptyFigureAndEmptyPanelStillRender) {
  Figure f;
  EXPECT_TRUE(test::check_xml(render(f)).ok);
  f.panels.push_back(Panel{});
  const test::XmlCheck x = test::check_xml(render(f));
  EXPECT_TRUE(x.ok) << x.error;
  EXPECT_EQ(x.count("path"), 0u);
}

}  // namespace
}  // namespace rt::svg
