#include "tools/evaluate/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "io/io_error.hpp"

namespace dammloam::eval {
namespace {

constexpr double kWidth = 900.0, kHeight = 700.0;
constexpr double kLeft = 80.0, kRight = 200.0, kTop = 40.0, kBottom = 60.0;  // margins, px

// A 1-2-5 step giving about `target` intervals over `range`.
double NiceStep(double range, int target) {
  const double raw = range / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double factor : {1.0, 2.0, 5.0}) {
    if (factor * magnitude >= raw) return factor * magnitude;
  }
  return 10.0 * magnitude;
}

std::string Num(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f", value);
  return text;
}

std::string Label(double metres) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", std::abs(metres) < 1e-9 ? 0.0 : metres);
  return text;
}

// World x-y (metres) to SVG pixels with one scale for both axes, y flipped.
struct Frame {
  double x_min, y_min, x_max, y_max, scale;
  double Px(double x) const { return kLeft + (x - x_min) * scale; }
  double Py(double y) const { return kTop + (y_max - y) * scale; }
};

Frame FitFrame(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  double x_min = std::numeric_limits<double>::max(), y_min = x_min;
  double x_max = std::numeric_limits<double>::lowest(), y_max = x_max;
  for (const auto* list : {&a, &b}) {
    for (const auto& p : *list) {
      x_min = std::min(x_min, p.x()), x_max = std::max(x_max, p.x());
      y_min = std::min(y_min, p.y()), y_max = std::max(y_max, p.y());
    }
  }
  if (x_min > x_max) x_min = y_min = -1.0, x_max = y_max = 1.0;  // nothing to draw
  const double pad = 0.05 * std::max({x_max - x_min, y_max - y_min, 1.0});
  x_min -= pad, x_max += pad, y_min -= pad, y_max += pad;
  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  const double scale = std::min(plot_w / (x_max - x_min), plot_h / (y_max - y_min));
  // Grow the smaller extent so the frame fills the plot area at equal scale.
  const double extra_x = (plot_w / scale - (x_max - x_min)) / 2.0;
  const double extra_y = (plot_h / scale - (y_max - y_min)) / 2.0;
  return {x_min - extra_x, y_min - extra_y, x_max + extra_x, y_max + extra_y, scale};
}

void Axes(std::ostream& svg, const Frame& f) {
  const double step = NiceStep(std::max(f.x_max - f.x_min, f.y_max - f.y_min), 8);
  svg << "<rect x=\"" << Num(kLeft) << "\" y=\"" << Num(kTop) << "\" width=\""
      << Num(f.Px(f.x_max) - kLeft) << "\" height=\"" << Num(f.Py(f.y_min) - kTop)
      << "\" fill=\"none\" stroke=\"#444\"/>\n";
  svg << "<g font-size=\"12\" fill=\"#333\">\n";
  for (double x = std::ceil(f.x_min / step) * step; x <= f.x_max; x += step) {
    svg << "<line x1=\"" << Num(f.Px(x)) << "\" y1=\"" << Num(kTop) << "\" x2=\"" << Num(f.Px(x))
        << "\" y2=\"" << Num(f.Py(f.y_min)) << "\" stroke=\"#ddd\"/>\n";
    svg << "<text x=\"" << Num(f.Px(x)) << "\" y=\"" << Num(f.Py(f.y_min) + 16)
        << "\" text-anchor=\"middle\">" << Label(x) << "</text>\n";
  }
  for (double y = std::ceil(f.y_min / step) * step; y <= f.y_max; y += step) {
    svg << "<line x1=\"" << Num(kLeft) << "\" y1=\"" << Num(f.Py(y)) << "\" x2=\"" << Num(f.Px(f.x_max))
        << "\" y2=\"" << Num(f.Py(y)) << "\" stroke=\"#ddd\"/>\n";
    svg << "<text x=\"" << Num(kLeft - 6) << "\" y=\"" << Num(f.Py(y) + 4)
        << "\" text-anchor=\"end\">" << Label(y) << "</text>\n";
  }
  svg << "<text x=\"" << Num((kLeft + f.Px(f.x_max)) / 2) << "\" y=\"" << Num(kHeight - 15)
      << "\" text-anchor=\"middle\">x [m]</text>\n";
  svg << "<text x=\"20\" y=\"" << Num((kTop + f.Py(f.y_min)) / 2)
      << "\" text-anchor=\"middle\" transform=\"rotate(-90 20 " << Num((kTop + f.Py(f.y_min)) / 2)
      << ")\">y [m]</text>\n";
  // Scale bar below the legend: one grid step.
  const double bar_x = kWidth - kRight + 20, bar_y = kTop + 150;
  svg << "<line x1=\"" << Num(bar_x) << "\" y1=\"" << Num(bar_y) << "\" x2=\""
      << Num(bar_x + step * f.scale) << "\" y2=\"" << Num(bar_y)
      << "\" stroke=\"#000\" stroke-width=\"3\"/>\n";
  svg << "<text x=\"" << Num(bar_x) << "\" y=\"" << Num(bar_y + 18) << "\">" << Label(step)
      << " m</text>\n";
  svg << "</g>\n";
}

void Trajectory(std::ostream& svg, const Frame& f, const std::vector<Eigen::Vector3d>& points,
                const char* colour) {
  if (points.empty()) return;
  svg << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\" points=\"";
  for (const auto& p : points) svg << Num(f.Px(p.x())) << ',' << Num(f.Py(p.y())) << ' ';
  svg << "\"/>\n";
  const auto& start = points.front();
  const auto& end = points.back();
  svg << "<circle cx=\"" << Num(f.Px(start.x())) << "\" cy=\"" << Num(f.Py(start.y()))
      << "\" r=\"6\" fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\"/>\n";
  svg << "<rect x=\"" << Num(f.Px(end.x()) - 5) << "\" y=\"" << Num(f.Py(end.y()) - 5)
      << "\" width=\"10\" height=\"10\" fill=\"" << colour << "\"/>\n";
}

void Legend(std::ostream& svg) {
  const double x = kWidth - kRight + 20;
  svg << "<g font-size=\"13\" fill=\"#000\">\n"
      << "<line x1=\"" << Num(x) << "\" y1=\"" << Num(kTop + 10) << "\" x2=\"" << Num(x + 30)
      << "\" y2=\"" << Num(kTop + 10) << "\" stroke=\"#222\" stroke-width=\"2\"/>\n"
      << "<text x=\"" << Num(x + 38) << "\" y=\"" << Num(kTop + 14) << "\">ground truth</text>\n"
      << "<line x1=\"" << Num(x) << "\" y1=\"" << Num(kTop + 35) << "\" x2=\"" << Num(x + 30)
      << "\" y2=\"" << Num(kTop + 35) << "\" stroke=\"#d62728\" stroke-width=\"2\"/>\n"
      << "<text x=\"" << Num(x + 38) << "\" y=\"" << Num(kTop + 39) << "\">estimate (aligned)</text>\n"
      << "<circle cx=\"" << Num(x + 15) << "\" cy=\"" << Num(kTop + 60)
      << "\" r=\"6\" fill=\"none\" stroke=\"#000\" stroke-width=\"2\"/>\n"
      << "<text x=\"" << Num(x + 38) << "\" y=\"" << Num(kTop + 64) << "\">start</text>\n"
      << "<rect x=\"" << Num(x + 10) << "\" y=\"" << Num(kTop + 80)
      << "\" width=\"10\" height=\"10\" fill=\"#000\"/>\n"
      << "<text x=\"" << Num(x + 38) << "\" y=\"" << Num(kTop + 89) << "\">end</text>\n"
      << "</g>\n";
}

}  // namespace

void WriteTopViewSvg(const std::filesystem::path& file, const std::vector<Eigen::Vector3d>& gt,
                     const std::vector<Eigen::Vector3d>& est) {
  const Frame frame = FitFrame(gt, est);
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << Num(kWidth) << "\" height=\""
      << Num(kHeight) << "\" viewBox=\"0 0 " << Num(kWidth) << ' ' << Num(kHeight) << "\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"#fff\"/>\n";
  Axes(svg, frame);
  Trajectory(svg, frame, gt, "#222");
  Trajectory(svg, frame, est, "#d62728");
  Legend(svg);
  svg << "</svg>\n";
  std::ofstream out(file);
  out << svg.str();
  if (!out) throw io::IoError(file.string() + ": cannot write SVG plot");
}

}  // namespace dammloam::eval
