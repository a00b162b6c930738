// The resource model's calibration page (resource_page.hpp).
#include "parallax/reports/resource_page.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "html_text.hpp"
#include "parallax/reports/report.hpp"

namespace parallax::reports {

namespace {

const char* const kGroupColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#7f7f7f"};

struct Dot {
  double published, predicted;
  std::string group, tip;
};

std::string fmt(double v, const char* f = "%.1f") {
  char b[48];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// Predicted against published on log-log axes: the diagonal, +-20 % and +-40 % bands, one colour
// per group. Zero values are drawn at the axis floor (0.5).
std::string svg_published_vs_predicted(const std::string& id, const std::string& title, const std::vector<Dot>& dots,
                                       const std::vector<std::string>& groups) {
  const double W = 420, H = 380, L = 56, R = 110, T = 30, B = 44;
  double hi = 1;
  for (const auto& d : dots) hi = std::max({hi, d.published, d.predicted});
  const double lo_log = std::log10(0.5), hi_log = std::log10(hi) + 0.1;
  auto sx = [&](double v) { return L + (std::log10(std::max(v, 0.5)) - lo_log) / (hi_log - lo_log) * (W - L - R); };
  auto sy = [&](double v) { return H - B - (std::log10(std::max(v, 0.5)) - lo_log) / (hi_log - lo_log) * (H - T - B); };
  std::ostringstream o;
  o << "<svg class=\"plot\" id=\"" << id << "\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\""
    << H << "\"><text x=\"" << (L + W - R) / 2 << "\" y=\"18\" text-anchor=\"middle\" class=\"t\">"
    << html_escape(title) << "</text><rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W - L - R << "\" height=\""
    << H - T - B << "\" fill=\"none\" stroke=\"#999\"/>";
  for (double decade = 1; decade <= hi * 1.01; decade *= 10)
    o << "<text x=\"" << sx(decade) << "\" y=\"" << H - B + 14 << "\" text-anchor=\"middle\" class=\"k\">"
      << number(decade) << "</text><text x=\"" << L - 4 << "\" y=\"" << sy(decade) + 4
      << "\" text-anchor=\"end\" class=\"k\">" << number(decade) << "</text>";
  const double top = std::pow(10.0, hi_log);
  for (const auto& band : {std::make_pair(1.0, "#444"), std::make_pair(1.2, "#9c9"), std::make_pair(0.8, "#9c9"),
                           std::make_pair(1.4, "#fc9"), std::make_pair(0.6, "#fc9")})
    o << "<line x1=\"" << sx(1) << "\" y1=\"" << sy(band.first) << "\" x2=\"" << sx(top) << "\" y2=\""
      << sy(top * band.first) << "\" stroke=\"" << band.second << "\" stroke-dasharray=\""
      << (band.first == 1.0 ? "0" : "4 3") << "\"/>";
  o << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 8 << "\" text-anchor=\"middle\">published</text>"
    << "<text transform=\"translate(14," << (T + H - B) / 2
    << ") rotate(-90)\" text-anchor=\"middle\">predicted (left out)</text>";
  for (const auto& d : dots) {
    const std::size_t g = std::size_t(std::find(groups.begin(), groups.end(), d.group) - groups.begin());
    o << "<circle class=\"pt\" cx=\"" << sx(d.published) << "\" cy=\"" << sy(d.predicted) << "\" r=\"4\" fill=\""
      << kGroupColours[g % 7] << "\" fill-opacity=\"0.75\"><title>" << html_escape(d.tip) << "</title></circle>";
  }
  double ly = T + 8;
  for (std::size_t g = 0; g < groups.size(); ++g, ly += 15)
    o << "<circle cx=\"" << W - R + 14 << "\" cy=\"" << ly << "\" r=\"4\" fill=\"" << kGroupColours[g % 7]
      << "\"/><text x=\"" << W - R + 24 << "\" y=\"" << ly + 4 << "\" class=\"k\">" << html_escape(groups[g])
      << "</text>";
  o << "<text x=\"" << W - R + 8 << "\" y=\"" << ly + 12 << "\" class=\"k\">dashed: &#177;20, &#177;40 %</text></svg>";
  return o.str();
}

std::string stats_row(const char* label, const res::ErrorStats& s) {
  return std::string("<tr><td class=\"s\">") + label + "</td><td>" + std::to_string(s.rows) + "</td><td>" +
         fmt(100.0 * s.exact_share()) + " %</td><td>" + fmt(s.median_pct) + " %</td><td>" + fmt(s.p90_pct) +
         " %</td></tr>";
}

std::string cell(int64_t v) {
  return v < 0 ? "<td>&ndash;</td>" : "<td>" + std::to_string(v) + "</td>";
}

}  // namespace

std::string resource_model_page(const res::FitResult& fit, res::Flavour flavour, const std::string& points_path) {
  std::vector<std::string> groups;
  for (const auto& r : fit.rows)
    if (r.described && std::find(groups.begin(), groups.end(), r.group) == groups.end()) groups.push_back(r.group);
  std::ostringstream o;
  o << "<h1>Resource model: predicted against published</h1><p>estimate: <b>" << res::flavour_name(flavour)
    << "</b> (the published rows are Vitis HLS C-synthesis estimates). " << fit.fitted_rows << " of " << fit.rows.size()
    << " rows fitted on, from " << html_escape(points_path)
    << "; each dot is predicted with coefficients fitted without its function (leave one family out); this "
       "project's designs are validation only.</p><div class=\"plots\">";
  for (int r = 0; r < res::kResourceCount; ++r) {
    std::vector<Dot> dots;
    for (const auto& row : fit.rows) {
      const int64_t pub = res::pick(row.published, r);
      if (!row.described || pub < 0) continue;
      const int64_t pred = res::pick(row.lofo, r);
      dots.push_back({double(pub), double(pred), row.group,
                      row.kernel + " (" + row.design + "): published " + std::to_string(pub) + ", predicted " +
                          std::to_string(pred)});
    }
    o << svg_published_vs_predicted(std::string("res-") + res::resource_name(r), res::resource_name(r), dots, groups);
  }
  o << "</div><h2>Errors</h2>";
  for (int r = 0; r < res::kResourceCount; ++r) {
    const res::ResourceStats& s = fit.stats[r];
    o << "<h3>" << res::resource_name(r) << "</h3><table class=\"kv\"><tr><th class=\"s\">predicted</th><th>rows</th>"
      << "<th>exact</th><th>median |error|</th><th>p90 |error|</th></tr>" << stats_row("fitted on all", s.fitted)
      << stats_row("leave one out", s.loo) << stats_row("leave one family out", s.lofo)
      << stats_row("leave one group out", s.logo) << "</table>";
  }
  o << "<h2>Rows</h2><table class=\"kv\"><tr><th class=\"s\">kernel</th><th class=\"s\">design</th>"
    << "<th class=\"s\">function</th><th>BRAM pub</th><th>pred</th><th>DSP pub</th><th>pred</th><th>FF pub</th>"
    << "<th>pred</th><th>LUT pub</th><th>pred</th></tr>";
  for (const auto& row : fit.rows) {
    o << "<tr><td class=\"s\">" << html_escape(row.kernel) << "</td><td class=\"s\">" << html_escape(row.design)
      << "</td>";
    if (!row.described) {
      o << "<td class=\"s\" colspan=\"9\">not described: " << html_escape(row.not_described) << "</td></tr>";
      continue;
    }
    o << "<td class=\"s\">" << html_escape(row.function) << (row.validation_only ? " (validation)" : "") << "</td>";
    for (int r = 0; r < res::kResourceCount; ++r)
      o << cell(res::pick(row.published, r)) << cell(res::pick(row.lofo, r));
    o << "</tr>";
  }
  o << "</table>";
  return standalone_page("Parallax resource model", o.str());
}

}  // namespace parallax::reports
