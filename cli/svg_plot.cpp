#include "svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dynpm/text.h"

namespace dynpm::cli {

std::string format_number(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

namespace {

// A "nice" tick spacing (1, 2 or 5 × 10^k) giving about `count` intervals over [0, range].
double nice_step(double range, int count) {
  if (!(range > 0)) return 1;
  const double raw = range / count;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * power) return m * power;
  return 10 * power;
}

}  // namespace

std::string svg_plot(const LevelsTable& table, const std::string& max_label, uint32_t full_vertices,
                     const std::string& title) {
  const std::vector<LevelRow>& rows = table.rows;
  const std::vector<size_t>& steps = table.steps;
  const double width = 760, height = 480, left = 80, right = 200, top = 50, bottom = 60;
  const double plot_w = width - left - right, plot_h = height - top - bottom;
  auto x_of = [&](const LevelRow& r) { return 100.0 * r.vertices / full_vertices; };
  double x_lo = 100, x_hi = 0, y_hi = 0;
  for (const LevelRow& r : rows) {
    x_lo = std::min(x_lo, x_of(r));
    x_hi = std::max(x_hi, x_of(r));
    y_hi = std::max(y_hi, r.max.hausdorff_pct);
    for (const LevelDistance& c : r.steps) y_hi = std::max(y_hi, c.hausdorff_pct);
  }
  // Whole decades around the data (at least one decade wide).
  double lx0 = std::floor(std::log10(std::max(x_lo, 1e-6)) + 0.02);  // 0.997 % → 1
  double lx1 = std::ceil(std::log10(std::max(x_hi, 1e-6)) - 0.02);
  if (lx1 <= lx0) lx1 = lx0 + 1;
  const double y_step = nice_step(y_hi > 0 ? y_hi : 1, 5);
  const double y_top = std::max(y_step, std::ceil(y_hi / y_step) * y_step);
  auto px = [&](double x) {
    return left + (std::log10(std::max(x, 1e-6)) - lx0) / (lx1 - lx0) * plot_w;
  };
  auto py = [&](double y) { return top + plot_h - y / y_top * plot_h; };

  std::string s;
  char buf[512];
  auto add = [&](const char* format, auto... values) {
    std::snprintf(buf, sizeof buf, format, values...);
    s += buf;
  };
  add("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" viewBox=\"0 0 %g "
      "%g\" font-family=\"sans-serif\" font-size=\"12\">\n",
      width, height, width, height);
  add("<rect width=\"%g\" height=\"%g\" fill=\"white\"/>\n", width, height);
  s += "<text x=\"" + format_number(left + plot_w / 2) +
       "\" y=\"24\" text-anchor=\"middle\" font-size=\"14\">" + xml_escaped(title) + "</text>\n";
  // Grid, ticks and labels.
  for (double d = lx0; d <= lx1 + 1e-9; ++d)
    for (int m : {1, 2, 5}) {
      const double x = m * std::pow(10.0, d);
      if (std::log10(x) > lx1 + 1e-9) break;
      const double X = px(x);
      add("<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"%s\"/>\n", X, top, X,
          top + plot_h, m == 1 ? "#ccc" : "#eee");
      add("<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\">%s</text>\n", X, top + plot_h + 18,
          format_number(x).c_str());
    }
  for (double y = 0; y <= y_top + y_step * 1e-6; y += y_step) {
    const double Y = py(y);
    add("<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"#ddd\"/>\n", left, Y,
        left + plot_w, Y);
    add("<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"end\">%s</text>\n", left - 6, Y + 4,
        format_number(y).c_str());
  }
  add("<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"black\"/>\n", left,
      top, plot_w, plot_h);
  add("<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\">vertices (%% of %u, log scale)</text>\n",
      left + plot_w / 2, height - 16, full_vertices);
  add("<text transform=\"translate(%g %.2f) rotate(-90)\" text-anchor=\"middle\">two-sided "
      "Hausdorff distance (%% of the diagonal)</text>\n",
      22.0, top + plot_h / 2);

  // Series: the chosen steps, then the max (black, dashed).
  static const char* const kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                         "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  std::vector<size_t> order(rows.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return x_of(rows[a]) < x_of(rows[b]); });
  for (size_t k = 0; k <= steps.size(); ++k) {
    const bool is_max = k == steps.size();
    const char* colour = is_max ? "black" : kColours[k % 10];
    std::string points;
    for (size_t i : order) {
      const double y = is_max ? rows[i].max.hausdorff_pct : rows[i].steps[k].hausdorff_pct;
      points += format_number(px(x_of(rows[i])), 6) + "," + format_number(py(y), 6) + " ";
    }
    s += std::string("<polyline fill=\"none\" stroke=\"") + colour + "\" stroke-width=\"2\"" +
         (is_max ? " stroke-dasharray=\"6 4\"" : "") + " points=\"" + points + "\"/>\n";
    for (size_t i : order) {
      const double y = is_max ? rows[i].max.hausdorff_pct : rows[i].steps[k].hausdorff_pct;
      add("<circle cx=\"%.2f\" cy=\"%.2f\" r=\"3\" fill=\"%s\"/>\n", px(x_of(rows[i])), py(y),
          colour);
    }
    // Legend entry.
    const double ly = top + 10 + 20 * double(k), lx = left + plot_w + 16;
    add("<line x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" stroke=\"%s\" stroke-width=\"2\"%s/>"
        "\n",
        lx, ly, lx + 24, ly, colour, is_max ? " stroke-dasharray=\"6 4\"" : "");
    const std::string label = is_max ? max_label : "step " + std::to_string(steps[k]);
    add("<text x=\"%.2f\" y=\"%.2f\">%s</text>\n", lx + 30, ly + 4, xml_escaped(label).c_str());
  }
  s += "</svg>\n";
  return s;
}

}  // namespace dynpm::cli
