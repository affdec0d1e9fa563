// A plain SVG line chart for the calibration report.
#pragma once

#include <string>
#include <tuple>
#include <vector>

namespace chainsim {

// one line: label, colour, y values (one per t)
using SvgSeries = std::tuple<std::string, std::string, std::vector<double>>;

// a 900 x 260 chart of the series over t with a legend
std::string svg_chart(const std::string& title, const std::string& ylabel, const std::vector<double>& t,
                      const std::vector<SvgSeries>& series);

// one panel of a grid: its own time axis, series and vertical marks (times)
struct SvgPanel {
  std::string title, ylabel;
  std::vector<double> t;
  std::vector<SvgSeries> series;
  std::vector<double> marks;
};

// panels in a grid of `cols` columns (each 300 x 200), one legend for all
std::string svg_panel_grid(const std::string& title, const std::vector<SvgPanel>& panels, int cols);

}  // namespace chainsim
