#include "analysis/calibration/svg_chart.h"

#include <algorithm>
#include <sstream>

#include "analysis/calibration/text_format.h"

namespace chainsim {

std::string svg_chart(const std::string& title, const std::string& ylabel, const std::vector<double>& t,
                      const std::vector<SvgSeries>& series) {
  const double W = 900, H = 260, L = 60, R = 150, T = 28, B = 34;
  double y0 = 1e300, y1 = -1e300;
  for (const auto& s : series)
    for (double v : std::get<2>(s)) y0 = std::min(y0, v), y1 = std::max(y1, v);
  if (!(y1 > y0)) y1 = y0 + 1;
  const double pad = 0.05 * (y1 - y0);
  y0 -= pad, y1 += pad;
  const double t0 = t.front(), t1 = t.back();
  auto X = [&](double x) { return L + (x - t0) / (t1 - t0) * (W - L - R); };
  auto Y = [&](double y) { return T + (y1 - y) / (y1 - y0) * (H - T - B); };
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
    << "' font-family='sans-serif' font-size='11'>\n<rect width='100%' height='100%' fill='white'/>\n";
  s << "<text x='" << L << "' y='16' font-size='13'>" << title << "</text>\n";
  s << "<rect x='" << L << "' y='" << T << "' width='" << (W - L - R) << "' height='" << (H - T - B)
    << "' fill='none' stroke='#888'/>\n";
  for (int i = 0; i <= 4; ++i) {
    const double yv = y0 + (y1 - y0) * i / 4, xv = t0 + (t1 - t0) * i / 4;
    s << "<text x='" << (L - 4) << "' y='" << Y(yv) + 4 << "' text-anchor='end'>" << fmt_g(yv, 3) << "</text>\n";
    s << "<text x='" << X(xv) << "' y='" << (H - B + 14) << "' text-anchor='middle'>" << fmt_g(xv, 3)
      << "</text>\n";
  }
  s << "<text x='" << (W - R) / 2 << "' y='" << (H - 4) << "'>t (s)</text>\n";
  s << "<text x='12' y='" << H / 2 << "' transform='rotate(-90 12 " << H / 2 << ")'>" << ylabel << "</text>\n";
  const size_t n = t.size(), stride = std::max<size_t>(1, n / 1500);
  int li = 0;
  for (const auto& [label, colour, y] : series) {
    s << "<polyline fill='none' stroke='" << colour << "' stroke-width='1' points='";
    for (size_t k = 0; k < n; k += stride) s << fmt_g(X(t[k]), 6) << "," << fmt_g(Y(y[k]), 6) << " ";
    s << "'/>\n";
    s << "<line x1='" << (W - R + 10) << "' x2='" << (W - R + 30) << "' y1='" << (T + 10 + 16 * li)
      << "' y2='" << (T + 10 + 16 * li) << "' stroke='" << colour << "' stroke-width='2'/>";
    s << "<text x='" << (W - R + 35) << "' y='" << (T + 14 + 16 * li) << "'>" << label << "</text>\n";
    ++li;
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace chainsim

namespace chainsim {

std::string svg_panel_grid(const std::string& title, const std::vector<SvgPanel>& panels, int cols) {
  const double PW = 300, PH = 200, L = 52, R = 8, T = 22, B = 30, top = 28;
  const int rows = static_cast<int>((panels.size() + cols - 1) / cols);
  const double W = PW * cols, H = top + PH * rows + 24;
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
    << "' font-family='sans-serif' font-size='10'>\n<rect width='100%' height='100%' fill='white'/>\n";
  s << "<text x='8' y='18' font-size='13'>" << title << "</text>\n";
  for (size_t i = 0; i < panels.size(); ++i) {
    const SvgPanel& p = panels[i];
    const double ox = PW * (i % cols), oy = top + PH * (i / cols);
    double y0 = 1e300, y1 = -1e300;
    for (const auto& sr : p.series)
      for (double v : std::get<2>(sr)) y0 = std::min(y0, v), y1 = std::max(y1, v);
    if (!(y1 > y0)) y1 = y0 + 1;
    const double pad = 0.05 * (y1 - y0);
    y0 -= pad, y1 += pad;
    const double t0 = p.t.front(), t1 = p.t.back() > t0 ? p.t.back() : t0 + 1e-3;
    auto X = [&](double x) { return ox + L + (x - t0) / (t1 - t0) * (PW - L - R); };
    auto Y = [&](double y) { return oy + T + (y1 - y) / (y1 - y0) * (PH - T - B); };
    s << "<text x='" << ox + L << "' y='" << oy + 14 << "'>" << p.title << "</text>\n";
    s << "<rect x='" << ox + L << "' y='" << oy + T << "' width='" << (PW - L - R) << "' height='" << (PH - T - B)
      << "' fill='none' stroke='#888'/>\n";
    for (int k = 0; k <= 2; ++k) {
      const double yv = y0 + (y1 - y0) * k / 2, xv = t0 + (t1 - t0) * k / 2;
      s << "<text x='" << ox + L - 3 << "' y='" << Y(yv) + 3 << "' text-anchor='end'>" << fmt_g(yv, 4) << "</text>\n";
      s << "<text x='" << X(xv) << "' y='" << oy + PH - B + 12 << "' text-anchor='middle'>" << fmt_g(xv, 4)
        << "</text>\n";
    }
    s << "<text x='" << ox + 10 << "' y='" << oy + PH / 2 << "' transform='rotate(-90 " << ox + 10 << " " << oy + PH / 2
      << ")'>" << p.ylabel << "</text>\n";
    for (double m : p.marks)
      if (m >= t0 && m <= t1)
        s << "<line x1='" << X(m) << "' x2='" << X(m) << "' y1='" << oy + T << "' y2='" << oy + PH - B
          << "' stroke='#2ca02c' stroke-dasharray='3,3'/>\n";
    for (const auto& [label, colour, y] : p.series) {
      s << "<polyline fill='none' stroke='" << colour << "' stroke-width='1' points='";
      for (size_t k = 0; k < p.t.size(); ++k) s << fmt_g(X(p.t[k]), 6) << "," << fmt_g(Y(y[k]), 6) << " ";
      s << "'/>\n";
    }
  }
  // one legend, from the first panel's series
  double lx = 8;
  if (!panels.empty())
    for (const auto& sr : panels.front().series) {
      s << "<line x1='" << lx << "' x2='" << lx + 18 << "' y1='" << H - 10 << "' y2='" << H - 10 << "' stroke='"
        << std::get<1>(sr) << "' stroke-width='2'/><text x='" << lx + 22 << "' y='" << H - 6 << "'>"
        << std::get<0>(sr) << "</text>\n";
      lx += 40 + 7 * std::get<0>(sr).size();
    }
  if (!panels.empty() && !panels.front().marks.empty())
    s << "<line x1='" << lx << "' x2='" << lx + 18 << "' y1='" << H - 10 << "' y2='" << H - 10
      << "' stroke='#2ca02c' stroke-dasharray='3,3'/><text x='" << lx + 22 << "' y='" << H - 6
      << "'>fitted frame edges</text>\n";
  s << "</svg>\n";
  return s.str();
}

}  // namespace chainsim
