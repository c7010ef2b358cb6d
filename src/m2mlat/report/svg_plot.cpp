// SVG output. Coordinates are written with one decimal: a tenth of a pixel is finer than any screen
// or printer shows and keeps the page small.
#include "m2mlat/report/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace m2mlat::report {

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return ticks;
  const double raw = (hi - lo) / std::max(1, target);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= raw) {
      step = m * power;
      break;
    }
  for (double t = std::ceil(lo / step) * step; t <= hi + step * 1e-9; t += step)
    ticks.push_back(std::fabs(t) < step * 1e-9 ? 0.0 : t);
  return ticks;
}

std::string tick_label(double value, double step) {
  int decimals = 0;
  if (step > 0 && step < 1) decimals = static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  return fmt::format("{:.{}f}", value, std::min(decimals, 9));
}

std::string xml_escape(std::string_view text) {
  std::string out;
  for (char ch : text) switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += ch;
    }
  return out;
}

std::string_view palette(std::size_t index) {
  static constexpr std::array<std::string_view, 8> kColours{"#0072B2", "#E69F00", "#009E73", "#D55E00",
                                                            "#CC79A7", "#56B4E9", "#F0E442", "#000000"};
  return kColours[index % kColours.size()];
}

SvgPlot::SvgPlot(std::string chart, std::string title, std::string x_label, std::string y_label, double x_lo,
                 double x_hi, double y_lo, double y_hi, int width, int height)
    : chart_(std::move(chart)),
      title_(std::move(title)),
      x_label_(std::move(x_label)),
      y_label_(std::move(y_label)),
      x_lo_(x_lo),
      x_hi_(x_hi > x_lo ? x_hi : x_lo + 1),
      y_lo_(y_lo),
      y_hi_(y_hi > y_lo ? y_hi : y_lo + 1),
      width_(width),
      height_(height) {}

double SvgPlot::px(double x) const {
  return left_ + (x - x_lo_) / (x_hi_ - x_lo_) * (width_ - left_ - right_);
}
double SvgPlot::py(double y) const {
  return height_ - bottom_ - (y - y_lo_) / (y_hi_ - y_lo_) * (height_ - top_ - bottom_);
}

void SvgPlot::set_x_categories(std::vector<std::pair<double, std::string>> categories) {
  categories_ = std::move(categories);
}

void SvgPlot::polyline(const std::vector<double>& xs, const std::vector<double>& ys, std::string_view colour,
                       std::string_view css_class) {
  if (xs.empty()) return;
  std::string points;
  for (std::size_t i = 0; i < xs.size(); ++i) points += fmt::format("{:.1f},{:.1f} ", px(xs[i]), py(ys[i]));
  points.pop_back();
  marks_ += fmt::format("<polyline class=\"{}\" stroke=\"{}\" points=\"{}\"/>\n", css_class, colour, points);
}

void SvgPlot::step_line(const std::vector<double>& xs, const std::vector<double>& ys,
                        std::string_view colour) {
  std::vector<double> sx, sy;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    if (i > 0) {
      sx.push_back(xs[i]);
      sy.push_back(ys[i - 1]);
    }
    sx.push_back(xs[i]);
    sy.push_back(ys[i]);
  }
  polyline(sx, sy, colour);
}

void SvgPlot::band(const std::vector<double>& xs, const std::vector<double>& lo,
                   const std::vector<double>& hi, std::string_view colour) {
  if (xs.empty()) return;
  std::string points;
  for (std::size_t i = 0; i < xs.size(); ++i) points += fmt::format("{:.1f},{:.1f} ", px(xs[i]), py(hi[i]));
  for (std::size_t i = xs.size(); i-- > 0;) points += fmt::format("{:.1f},{:.1f} ", px(xs[i]), py(lo[i]));
  points.pop_back();
  marks_ += fmt::format("<polygon class=\"band\" fill=\"{}\" points=\"{}\"/>\n", colour, points);
}

void SvgPlot::rect(double x0, double y0, double x1, double y1, std::string_view colour,
                   std::string_view css_class) {
  const double a = std::min(px(x0), px(x1)), b = std::min(py(y0), py(y1));
  const double w = std::fabs(px(x1) - px(x0)), h = std::max(0.5, std::fabs(py(y1) - py(y0)));
  marks_ += fmt::format(
      "<rect class=\"{}\" x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"{}\" "
      "stroke=\"{}\"/>\n",
      css_class, a, b, w, h, colour, colour);
}

void SvgPlot::segment(double x0, double y0, double x1, double y1, std::string_view colour,
                      std::string_view css_class) {
  marks_ += fmt::format(
      "<line class=\"{}\" x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"{}\"/>\n",
      css_class, px(x0), py(y0), px(x1), py(y1), colour);
}

void SvgPlot::circle(double x, double y, double r_px, std::string_view colour, std::string_view css_class) {
  marks_ += fmt::format("<circle class=\"{}\" cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"{:.1f}\" fill=\"{}\"/>\n",
                        css_class, px(x), py(y), r_px, colour);
}

void SvgPlot::hline(double y, std::string_view label, std::string_view css_class) {
  if (y < y_lo_ || y > y_hi_) return;
  marks_ += fmt::format(
      "<line class=\"{}\" x1=\"{}\" y1=\"{:.1f}\" x2=\"{}\" y2=\"{:.1f}\"/>"
      "<text class=\"reflabel\" x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>\n",
      css_class, left_, py(y), width_ - right_, py(y), width_ - right_ - 2, py(y) - 3, xml_escape(label));
}

void SvgPlot::legend(const std::vector<std::pair<std::string, std::string>>& entries) { legend_ = entries; }
void SvgPlot::note(std::string_view text) { note_ = text; }

std::string SvgPlot::render() const {
  // The legend sits in rows of its own between the title and the frame, never over the data: the
  // chart grows by their height and everything below them moves down.
  constexpr int kLegendRow = 16;
  std::vector<std::pair<double, int>> at;  // each entry's x and row
  double lx = left_;
  int rows = legend_.empty() ? 0 : 1;
  for (const auto& entry : legend_) {
    const double w = 7.2 * static_cast<double>(entry.first.size()) + 24;
    if (lx > left_ && lx + w > width_ - right_) lx = left_, ++rows;
    at.emplace_back(lx, rows - 1);
    lx += w;
  }
  const int shift = rows * kLegendRow;
  // Labels wider than the space between categories (11 px text: about 6 px a character) go on two
  // alternating rows; one still wider than two spaces is cut with an ellipsis, its whole name in a
  // tooltip. So neighbouring labels never overlap; the axis title moves down below a second row.
  constexpr double kCharPx = 6.0;
  double slot = static_cast<double>(width_ - left_ - right_);
  for (std::size_t k = 1; k < categories_.size(); ++k)
    slot = std::min(slot, std::fabs(px(categories_[k].first) - px(categories_[k - 1].first)));
  std::size_t widest = 0;
  for (const auto& category : categories_) widest = std::max(widest, category.second.size());
  const bool two_rows = !categories_.empty() && static_cast<double>(widest) * kCharPx > slot;
  const auto fits = static_cast<std::size_t>(std::max(3.0, (two_rows ? 2 * slot : slot) / kCharPx - 1));
  const int below = two_rows ? 13 : 0;  // px the second row of labels adds under the plot
  std::string s = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"chart\" data-chart=\"{}\" viewBox=\"0 0 {} {}\" "
      "role=\"img\" aria-label=\"{}\">\n<title>{}</title>\n",
      xml_escape(chart_), width_, height_ + shift + below, xml_escape(title_), xml_escape(title_));
  s += fmt::format("<text class=\"title\" x=\"{}\" y=\"16\">{}</text>\n", left_, xml_escape(title_));
  if (!note_.empty())
    s += fmt::format("<text class=\"note\" x=\"{}\" y=\"30\">{}</text>\n", left_, xml_escape(note_));
  for (std::size_t k = 0; k < legend_.size(); ++k) {
    const double y = top_ - 4 + at[k].second * kLegendRow;
    s += fmt::format(
        "<rect x=\"{:.1f}\" y=\"{}\" width=\"10\" height=\"10\" fill=\"{}\"/><text class=\"legend\" "
        "x=\"{:.1f}\" y=\"{}\">{}</text>\n",
        at[k].first, y, legend_[k].second, at[k].first + 13, y + 9, xml_escape(legend_[k].first));
  }
  s += fmt::format("<g transform=\"translate(0 {})\">\n", shift);
  const double plot_bottom = height_ - bottom_, plot_top = top_;
  // Grid and y ticks.
  const auto yt = nice_ticks(y_lo_, y_hi_, 6);
  const double ystep = yt.size() > 1 ? yt[1] - yt[0] : 1;
  for (double t : yt)
    s += fmt::format(
        "<line class=\"grid\" x1=\"{}\" y1=\"{:.1f}\" x2=\"{}\" y2=\"{:.1f}\"/><text class=\"tick\" "
        "x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text>\n",
        left_, py(t), width_ - right_, py(t), left_ - 4, py(t) + 4, tick_label(t, ystep));
  if (categories_.empty()) {
    const auto xt = nice_ticks(x_lo_, x_hi_, 8);
    const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1;
    for (double t : xt)
      s += fmt::format(
          "<line class=\"grid\" x1=\"{:.1f}\" y1=\"{}\" x2=\"{:.1f}\" y2=\"{}\"/><text class=\"tick\" "
          "x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n",
          px(t), plot_top, px(t), plot_bottom, px(t), plot_bottom + 14, tick_label(t, xstep));
  } else {
    for (std::size_t k = 0; k < categories_.size(); ++k) {
      const auto& [x, name] = categories_[k];
      const bool cut = name.size() > fits;
      std::size_t keep = fits - 1;
      while (cut && keep > 0 && (static_cast<unsigned char>(name[keep]) & 0xC0) == 0x80) --keep;  // whole UTF-8
      const std::string shown = cut ? name.substr(0, keep) + "\u2026" : name;
      s += fmt::format("<text class=\"tick\" x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{}{}</text>\n", px(x),
                       plot_bottom + (two_rows && k % 2 == 1 ? 27 : 14),
                       cut ? "<title>" + xml_escape(name) + "</title>" : std::string(), xml_escape(shown));
    }
  }
  s += fmt::format("<rect class=\"frame\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>\n", left_, top_,
                   width_ - left_ - right_, height_ - top_ - bottom_);
  s += "<g class=\"marks\">\n" + marks_ + "</g>\n";
  s += fmt::format("<text class=\"axis\" x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n",
                   (left_ + width_ - right_) / 2, height_ - 8 + below, xml_escape(x_label_));
  s += fmt::format(
      "<text class=\"axis\" transform=\"translate(14 {}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
      (top_ + height_ - bottom_) / 2, xml_escape(y_label_));
  return s + "</g>\n</svg>\n";
}

}  // namespace m2mlat::report
