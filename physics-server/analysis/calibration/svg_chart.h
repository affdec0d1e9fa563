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

}  // namespace chainsim
