// A small SVG plotting surface for the HTML report: a frame with linear axes, "nice" ticks, grid
// lines and labels, and the marks the charts need (polylines, rectangles, circles, error bars,
// filled bands). The output is plain inline SVG styled by the page's CSS classes, so the report
// needs no script and no network, and prints as vectors.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace m2mlat::report {

// Ticks at 1, 2 or 5 times a power of ten covering [lo, hi], about `target` of them.
std::vector<double> nice_ticks(double lo, double hi, int target = 6);
// The number as a tick label: as few decimals as the tick spacing needs.
std::string tick_label(double value, double step);
// Escapes &, <, >, " and ' for text and attributes.
std::string xml_escape(std::string_view text);
// One of eight colour-blind-safe colours (Okabe and Ito), by index.
std::string_view palette(std::size_t index);

class SvgPlot {
 public:
  // chart: the data-chart attribute (what the tests look for); the axes span [x_lo, x_hi] x [y_lo, y_hi].
  SvgPlot(std::string chart, std::string title, std::string x_label, std::string y_label, double x_lo,
          double x_hi, double y_lo, double y_hi, int width = 720, int height = 340);

  double px(double x) const;  // data -> pixel
  double py(double y) const;

  // Draw category labels instead of numeric ticks on x (positions in data units).
  void set_x_categories(std::vector<std::pair<double, std::string>> categories);

  void polyline(const std::vector<double>& xs, const std::vector<double>& ys, std::string_view colour,
                std::string_view css_class = "line");
  void step_line(const std::vector<double>& xs, const std::vector<double>& ys, std::string_view colour);
  void band(const std::vector<double>& xs, const std::vector<double>& lo, const std::vector<double>& hi,
            std::string_view colour);
  void rect(double x0, double y0, double x1, double y1, std::string_view colour,
            std::string_view css_class = "box");
  void segment(double x0, double y0, double x1, double y1, std::string_view colour,
               std::string_view css_class = "seg");
  void circle(double x, double y, double r_px, std::string_view colour, std::string_view css_class = "pt");
  void hline(double y, std::string_view label, std::string_view css_class = "ref");
  void legend(const std::vector<std::pair<std::string, std::string>>& entries);  // (name, colour)
  void note(std::string_view text);  // a small line under the title

  std::string render() const;

 private:
  std::string chart_, title_, x_label_, y_label_, note_;
  double x_lo_, x_hi_, y_lo_, y_hi_;
  int width_, height_;
  int left_ = 64, right_ = 16, top_ = 40, bottom_ = 48;
  std::vector<std::pair<double, std::string>> categories_;
  std::vector<std::pair<std::string, std::string>> legend_;
  std::string marks_;
};

}  // namespace m2mlat::report
