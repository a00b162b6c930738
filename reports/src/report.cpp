// Reports (report.hpp): CSV, JSON and one self-contained HTML page.
#include "parallax/reports/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include "html_text.hpp"
#include "rows.hpp"

namespace parallax::reports {

// The names this file takes from the other rooms besides its header's (one namespace per room).
using eval::InputError;
using search::beaten_on_accuracy_by;
using search::meets_constraints;
using search::pareto_front;
using search::peer_name;

namespace {

using rows::field;
using rows::metric;
using rows::path_count;

std::string base64(const std::vector<uchar>& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned(in[i]) << 16) | (unsigned(in[i + 1]) << 8) | in[i + 2];
    o += t[(v >> 18) & 63];
    o += t[(v >> 12) & 63];
    o += t[(v >> 6) & 63];
    o += t[v & 63];
  }
  if (i < in.size()) {
    const unsigned v = (unsigned(in[i]) << 16) | (i + 1 < in.size() ? unsigned(in[i + 1]) << 8 : 0u);
    o += t[(v >> 18) & 63];
    o += t[(v >> 12) & 63];
    o += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
    o += '=';
  }
  return o;
}

std::string img_tag(const cv::Mat& m, const std::string& caption) {
  if (m.empty()) return "";
  std::vector<uchar> png;
  cv::imencode(".png", m, png);
  return "<figure><img alt=\"" + html_escape(caption) + "\" src=\"data:image/png;base64," + base64(png) +
         "\"><figcaption>" + html_escape(caption) + "</figcaption></figure>";
}

const char* kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};

struct Point {
  double x, y;
  std::string colour_key, shape_key, label;
  bool front;
  std::string tag;  // a reference point (the seed, an OpenCV peer): a black diamond named beside it
};

// A scatter plot as inline SVG: colour by one key, marker shape (circle / square) by another,
// front designs outlined in black.
std::string svg_scatter(const std::string& id, const std::string& title, const std::string& xlabel,
                        const std::string& ylabel, const std::vector<Point>& pts) {
  const double W = 460, H = 320, L = 60, R = 120, T = 30, B = 45;
  std::vector<Point> p;
  for (const auto& q : pts)
    if (std::isfinite(q.x) && std::isfinite(q.y)) p.push_back(q);
  std::ostringstream o;
  o << "<svg class=\"plot\" id=\"" << id << "\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\""
    << H << "\" viewBox=\"0 0 " << W << " " << H << "\"><text x=\"" << W / 2
    << "\" y=\"18\" text-anchor=\"middle\" class=\"t\">" << html_escape(title) << "</text>";
  if (p.empty()) {
    o << "<text x=\"" << W / 2 << "\" y=\"" << H / 2 << "\" text-anchor=\"middle\">no data</text></svg>";
    return o.str();
  }
  double x0 = p[0].x, x1 = p[0].x, y0 = p[0].y, y1 = p[0].y;
  for (const auto& q : p) {
    x0 = std::min(x0, q.x);
    x1 = std::max(x1, q.x);
    y0 = std::min(y0, q.y);
    y1 = std::max(y1, q.y);
  }
  if (x1 - x0 < 1e-9) {
    x0 -= 1;
    x1 += 1;
  }
  if (y1 - y0 < 1e-9) {
    y0 -= 1;
    y1 += 1;
  }
  const double px = (x1 - x0) * 0.05, py = (y1 - y0) * 0.05;
  x0 -= px;
  x1 += px;
  y0 -= py;
  y1 += py;
  auto sx = [&](double x) { return L + (x - x0) / (x1 - x0) * (W - L - R); };
  auto sy = [&](double y) { return H - B - (y - y0) / (y1 - y0) * (H - T - B); };
  o << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W - L - R << "\" height=\"" << H - T - B
    << "\" fill=\"none\" stroke=\"#999\"/>";
  for (int i = 0; i <= 4; ++i) {
    const double xv = x0 + (x1 - x0) * i / 4, yv = y0 + (y1 - y0) * i / 4;
    o << "<text x=\"" << sx(xv) << "\" y=\"" << H - B + 14 << "\" text-anchor=\"middle\" class=\"k\">"
      << number(std::round(xv * 10) / 10) << "</text><text x=\"" << L - 4 << "\" y=\"" << sy(yv) + 4
      << "\" text-anchor=\"end\" class=\"k\">" << number(std::round(yv * 10) / 10) << "</text>";
  }
  o << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 8 << "\" text-anchor=\"middle\">" << html_escape(xlabel)
    << "</text><text transform=\"translate(14," << (T + H - B) / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
    << html_escape(ylabel) << "</text>";
  std::vector<std::string> colours, shapes;
  for (const auto& q : p) {
    if (!q.tag.empty()) continue;
    if (std::find(colours.begin(), colours.end(), q.colour_key) == colours.end()) colours.push_back(q.colour_key);
    if (std::find(shapes.begin(), shapes.end(), q.shape_key) == shapes.end()) shapes.push_back(q.shape_key);
  }
  auto colour = [&](const std::string& k) {
    return kPalette[std::size_t(std::find(colours.begin(), colours.end(), k) - colours.begin()) % 8];
  };
  auto marker = [&](const std::string& shape, double x, double y, const char* fill, bool front,
                    const std::string& tip) {
    const std::string stroke = front ? " stroke=\"#000\" stroke-width=\"2\"" : " stroke=\"none\"";
    std::ostringstream m;
    if (std::find(shapes.begin(), shapes.end(), shape) - shapes.begin() == 0)
      m << "<circle class=\"pt\" cx=\"" << x << "\" cy=\"" << y << "\" r=\"4.5\" fill=\"" << fill
        << "\" fill-opacity=\"0.8\"" << stroke << ">";
    else
      m << "<rect class=\"pt\" x=\"" << x - 4 << "\" y=\"" << y - 4 << "\" width=\"8\" height=\"8\" fill=\"" << fill
        << "\" fill-opacity=\"0.8\"" << stroke << ">";
    m << "<title>" << html_escape(tip) << "</title>"
      << (std::find(shapes.begin(), shapes.end(), shape) - shapes.begin() == 0 ? "</circle>" : "</rect>");
    return m.str();
  };
  for (const auto& q : p) {
    if (q.tag.empty()) {
      o << marker(q.shape_key, sx(q.x), sy(q.y), colour(q.colour_key), q.front, q.label);
      continue;
    }
    const double x = sx(q.x), y = sy(q.y);
    o << "<path class=\"ref\" d=\"M" << x << " " << y - 6 << " L" << x + 6 << " " << y << " L" << x << " " << y + 6
      << " L" << x - 6 << " " << y << " Z\" fill=\"#000\"><title>" << html_escape(q.label)
      << "</title></path><text x=\"" << x + 8 << "\" y=\"" << y - 6 << "\" class=\"k\">" << html_escape(q.tag)
      << "</text>";
  }
  double ly = T + 8;
  for (const auto& c : colours) {
    o << "<circle cx=\"" << W - R + 14 << "\" cy=\"" << ly << "\" r=\"4.5\" fill=\"" << colour(c) << "\"/><text x=\""
      << W - R + 24 << "\" y=\"" << ly + 4 << "\" class=\"k\">" << html_escape(c) << "</text>";
    ly += 15;
  }
  ly += 6;
  for (const auto& sh : shapes) {
    o << marker(sh, W - R + 14, ly, "#777", false, sh) << "<text x=\"" << W - R + 24 << "\" y=\"" << ly + 4
      << "\" class=\"k\">" << html_escape(sh) << "</text>";
    ly += 15;
  }
  o << "<text x=\"" << W - R + 8 << "\" y=\"" << ly + 10 << "\" class=\"k\">outlined: front</text>";
  if (std::any_of(p.begin(), p.end(), [](const Point& q) { return !q.tag.empty(); }))
    o << "<text x=\"" << W - R + 8 << "\" y=\"" << ly + 24 << "\" class=\"k\">&#9670;: seed, peers</text>";
  o << "</svg>";
  return o.str();
}

// Horizontal stacked bars: one row per label, segments (value, colour, name).
std::string svg_bars(const std::string& id, const std::string& title,
                     const std::vector<std::pair<std::string, std::vector<std::pair<double, std::string>>>>& rows,
                     const std::vector<std::pair<std::string, std::string>>& legend, double max_value,
                     const std::string& unit) {
  const double W = 560, L = 130, R = 20, row_h = 20, T = 30;
  const double H = T + row_h * double(rows.size()) + 52;
  std::ostringstream o;
  o << "<svg class=\"plot\" id=\"" << id << "\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\""
    << H << "\"><text x=\"" << W / 2 << "\" y=\"18\" text-anchor=\"middle\" class=\"t\">" << html_escape(title)
    << "</text>";
  if (!(max_value > 0)) max_value = 1;
  double y = T;
  for (const auto& r : rows) {
    o << "<text x=\"" << L - 6 << "\" y=\"" << y + 14 << "\" text-anchor=\"end\" class=\"k\">" << html_escape(r.first)
      << "</text>";
    double x = L;
    for (const auto& seg : r.second) {
      const double w = std::max(0.0, seg.first / max_value * (W - L - R));
      o << "<rect class=\"bar\" x=\"" << x << "\" y=\"" << y + 3 << "\" width=\"" << w << "\" height=\"" << row_h - 6
        << "\" fill=\"" << seg.second << "\"><title>" << html_escape(r.first) << ": " << number(seg.first) << " "
        << unit << "</title></rect>";
      x += w;
    }
    y += row_h;
  }
  double lx = L;
  for (const auto& item : legend) {
    o << "<rect x=\"" << lx << "\" y=\"" << y + 8 << "\" width=\"10\" height=\"10\" fill=\"" << item.second
      << "\"/><text x=\"" << lx + 14 << "\" y=\"" << y + 17 << "\" class=\"k\">" << html_escape(item.first)
      << "</text>";
    lx += 14 + 6.0 * double(item.first.size()) + 16;
  }
  o << "<text x=\"" << W - R << "\" y=\"" << y + 36
    << "\" text-anchor=\"end\" class=\"k\">full width = " << number(max_value) << " " << html_escape(unit)
    << "</text></svg>";
  return o.str();
}

const char* kStyle = R"CSS(
body{font-family:system-ui,-apple-system,"Segoe UI",sans-serif;margin:24px auto;max-width:1200px;color:#222;padding:0 16px}
h1{font-size:1.6em}h2{margin-top:2em;border-bottom:1px solid #ddd;padding-bottom:4px}
table{border-collapse:collapse;font-size:12px}th,td{border:1px solid #ddd;padding:3px 6px;text-align:right}
th{background:#f4f4f4;cursor:pointer;position:sticky;top:0}td.s,th.s{text-align:left}
tr.front td{background:#fff8dc}.plots{display:flex;flex-wrap:wrap;gap:12px}
svg.plot text{font-size:12px}svg.plot text.k{font-size:10px;fill:#444}svg.plot text.t{font-weight:600}
figure{display:inline-block;margin:6px}figure img{max-width:360px;image-rendering:pixelated;border:1px solid #ccc}
figcaption{font-size:12px;color:#555}pre{background:#f7f7f7;padding:8px;overflow:auto;font-size:12px}
.kv td{text-align:left}td.reason{max-width:420px;white-space:nowrap;overflow:hidden;text-overflow:ellipsis}.scroll{max-height:520px;overflow:auto;border:1px solid #eee}#filter{margin:8px 0;padding:4px;width:320px}
)CSS";

const char* kScript = R"JS(
(function(){
  var t=document.getElementById('designs'); if(!t) return;
  var f=document.getElementById('filter');
  f.addEventListener('input',function(){var q=f.value.toLowerCase();
    Array.prototype.forEach.call(t.tBodies[0].rows,function(r){r.style.display=r.textContent.toLowerCase().indexOf(q)<0?'none':'';});});
  Array.prototype.forEach.call(t.tHead.rows[0].cells,function(th,i){th.addEventListener('click',function(){
    var rows=Array.prototype.slice.call(t.tBodies[0].rows);var asc=th.getAttribute('data-asc')!=='1';th.setAttribute('data-asc',asc?'1':'0');
    rows.sort(function(a,b){var x=a.cells[i].textContent,y=b.cells[i].textContent;var nx=parseFloat(x),ny=parseFloat(y);
      var c=(!isNaN(nx)&&!isNaN(ny))?nx-ny:x.localeCompare(y);return asc?c:-c;});
    rows.forEach(function(r){t.tBodies[0].appendChild(r);});});});
})();
)JS";

}  // namespace

cv::Mat error_map(const cv::Mat& d, const cv::Mat& v, const cv::Mat& gt, const cv::Mat& gm) {
  cv::Mat out(d.size(), CV_8UC3, cv::Scalar(0, 0, 0));
  for (int y = 0; y < d.rows; ++y)
    for (int x = 0; x < d.cols; ++x) {
      if (!gm.at<uint8_t>(y, x) || !v.at<uint8_t>(y, x)) continue;
      const bool ok = std::fabs(d.at<float>(y, x) - gt.at<float>(y, x)) <= 3.0f;
      out.at<cv::Vec3b>(y, x) = ok ? cv::Vec3b(60, 180, 60) : cv::Vec3b(40, 40, 230);
    }
  return out;
}

void add_avoidance_images(DesignSection& s, const AvoidanceView& a) {
  auto grey = [](const cv::Mat& counts) {
    cv::Mat f;
    counts.convertTo(f, CV_32F);
    cv::log(f + 1.0f, f);
    double mx = 0;
    cv::minMaxLoc(f, nullptr, &mx);
    cv::Mat g;
    f.convertTo(g, CV_8U, mx > 0 ? 255.0 / mx : 1.0);
    cv::Mat bgr;
    cv::cvtColor(g, bgr, cv::COLOR_GRAY2BGR);
    return bgr;
  };
  if (a.u_map.empty() || a.v_map.empty()) return;
  const int su = 3, sv = 4;  // stretch the short disparity axes so that they can be seen
  cv::Mat u = grey(a.u_map), v = grey(a.v_map);
  cv::resize(u, u, cv::Size(u.cols, u.rows * su), 0, 0, cv::INTER_NEAREST);
  cv::resize(v, v, cv::Size(v.cols * sv, v.rows), 0, 0, cv::INTER_NEAREST);
  for (const auto& o : a.obstacles) {
    cv::rectangle(u, cv::Rect(o.u_box.x, o.u_box.y * su, o.u_box.width, o.u_box.height * su), cv::Scalar(60, 200, 60),
                  1);
    cv::RotatedRect e = o.ellipse;
    e.center.y *= su;
    e.size.height *= su;
    if (e.size.width > 1 && e.size.height > 1) cv::ellipse(u, e, cv::Scalar(40, 40, 230), 1);
    cv::rectangle(v, cv::Rect(o.v_box.x * sv, o.v_box.y, o.v_box.width * sv, o.v_box.height), cv::Scalar(60, 200, 60),
                  1);
  }
  if (a.ground_found)
    cv::line(v, cv::Point(0, int(a.ground_offset)),
             cv::Point(v.cols, int(a.ground_slope * a.max_disparity + a.ground_offset)), cv::Scalar(230, 120, 40), 1);
  s.u_map_image = u;
  s.v_map_image = v;
  s.metrics["obstacles"] = double(a.obstacles.size());
  if (!a.obstacles.empty()) s.metrics["nearest_obstacle_m"] = a.obstacles.front().range_m;
}

void add_flight(DesignSection& s, const FlightView& f) {
  // Top-down: x across, z up the page.
  const double W = 300, H = 420, x0 = -10, x1 = 10, z1 = f.goal_z_m + 2;
  auto sx = [&](double x) { return (x - x0) / (x1 - x0) * W; };
  auto sz = [&](double z) { return H - z / z1 * H; };
  std::ostringstream o;
  o << "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H + 20
    << "\"><rect width=\"" << W << "\" height=\"" << H << "\" fill=\"#f6f6f0\" stroke=\"#999\"/>";
  for (const auto& c : f.cylinders)
    o << "<circle cx=\"" << sx(c.x_m) << "\" cy=\"" << sz(c.z_m) << "\" r=\""
      << std::max(1.5, c.radius_m / (x1 - x0) * W) << "\" fill=\"#2e7d32\"/>";
  for (const auto& b : f.boxes)
    o << "<rect x=\"" << sx(std::max(b.x0_m, x0)) << "\" y=\"" << sz(b.z1_m) << "\" width=\""
      << sx(std::min(b.x1_m, x1)) - sx(std::max(b.x0_m, x0)) << "\" height=\"" << std::max(1.0, sz(b.z0_m) - sz(b.z1_m))
      << "\" fill=\"#8d6e63\"/>";
  o << "<polyline fill=\"none\" stroke=\"" << (f.collided ? "#d62728" : "#1f77b4") << "\" stroke-width=\"2\" points=\"";
  for (const auto& p : f.trajectory_xz_m) o << sx(p.x) << "," << sz(p.y) << " ";
  o << "\"/><line x1=\"0\" x2=\"" << W << "\" y1=\"" << sz(f.goal_z_m) << "\" y2=\"" << sz(f.goal_z_m)
    << "\" stroke=\"#444\" stroke-dasharray=\"4 3\"/><text x=\"4\" y=\"" << H + 15 << "\" class=\"k\">"
    << html_escape(f.scenario) << " at " << number(f.speed_mps) << " m/s: " << f.outcome << ", min clearance "
    << number(std::round(f.min_clearance_m * 100) / 100) << " m</text></svg>";
  s.flight_svg = o.str();
  for (const auto& frame : f.frames) {
    s.flight_frames.push_back({frame.left_grey, "flight frame " + std::to_string(frame.index)});
    s.flight_frames.push_back({frame.disparity_colour, "its disparity, frame " + std::to_string(frame.index)});
  }
}

void add_frame_images(DesignSection& s, const FrameView& f) {
  s.frame_id = f.frame_id;
  s.left_grey = f.left_grey;
  s.disparity_colour = f.disparity_colour;
  s.gt_colour = f.gt_colour;
  s.error_map = error_map(f.disparity_px, f.valid_mask, f.gt_px, f.gt_mask);
  add_avoidance_images(s, f.avoidance);
}

void add_figures(DesignSection& s, const DesignResult& r) {
  if (r.timing) s.cycle = r.timing->cycle;
  if (r.resources) {
    s.resources = r.resources->estimate;
    s.device = r.resources->utilisation.device;
  }
}

std::string design_section_html(const DesignSection& s) {
  std::ostringstream o;
  o << "<section class=\"design\"><h3>" << html_escape(s.title) << "</h3>";
  if (!s.metrics.empty()) {
    o << "<table class=\"kv\">";
    for (const auto& k : metric_columns())
      if (s.metrics.count(k)) o << "<tr><td>" << k << "</td><td>" << number(s.metrics.at(k)) << "</td></tr>";
    for (const char* k : {"obstacles", "nearest_obstacle_m"})
      if (s.metrics.count(k)) o << "<tr><td>" << k << "</td><td>" << number(s.metrics.at(k)) << "</td></tr>";
    o << "</table>";
  }
  if (!s.left_grey.empty()) {
    o << "<div class=\"images\">" << img_tag(s.left_grey, "left image, frame " + s.frame_id)
      << img_tag(s.disparity_colour, "disparity (red near, blue far, black invalid)")
      << img_tag(s.gt_colour, "ground truth")
      << img_tag(s.error_map, "error: green within 3 px, red beyond, black unscored")
      << img_tag(s.u_map_image, "U map (disparity x column, stretched x3): obstacles boxed, ellipses red")
      << img_tag(s.v_map_image, "V map (row x disparity, stretched x4): ground line blue, obstacles boxed") << "</div>";
  }
  if (!s.flight_svg.empty()) {
    o << "<h4>Flight</h4><div class=\"plots\">" << s.flight_svg << "</div><div class=\"images\">";
    for (const auto& f : s.flight_frames) o << img_tag(f.first, f.second);
    o << "</div>";
  }
  const std::string id = "d" + std::to_string(std::hash<std::string>{}(s.title) % 1000000);
  if (!s.cycle.stages.empty()) {
    std::vector<std::pair<std::string, std::vector<std::pair<double, std::string>>>> rows;
    double mx = 0;
    for (const auto& st : s.cycle.stages) {
      rows.push_back({st.name,
                      {{double(st.busy_cycles), kPalette[0]},
                       {double(st.input_stall_cycles), kPalette[1]},
                       {double(st.output_stall_cycles), kPalette[3]}}});
      mx = std::max(mx, double(st.busy_cycles + st.input_stall_cycles + st.output_stall_cycles));
    }
    o << "<div class=\"plots\">"
      << svg_bars(id + "-cycles",
                  "cycles per stage (last pixel at cycle " + std::to_string(s.cycle.last_pixel_cycle) + ")", rows,
                  {{"busy", kPalette[0]}, {"waiting for input", kPalette[1]}, {"waiting for space", kPalette[3]}}, mx,
                  "cycles");
    std::vector<std::pair<std::string, std::vector<std::pair<double, std::string>>>> fifos;
    double fmx = 0;
    for (const auto& f : s.cycle.fifos) {
      fifos.push_back(
          {f.name,
           {{double(f.high_water), kPalette[2]}, {double(std::max<int64_t>(0, f.depth - f.high_water)), "#ddd"}}});
      fmx = std::max(fmx, double(std::max(f.depth, f.high_water)));
    }
    o << svg_bars(id + "-fifos", "FIFO occupancy: high-water mark of the depth", fifos,
                  {{"high water", kPalette[2]}, {"unused depth", "#ddd"}}, fmx, "tokens")
      << "</div>";
  }
  if (s.device) {
    const res::Utilisation u = res::utilisation(s.resources.total, *s.device);
    std::vector<std::pair<std::string, std::vector<std::pair<double, std::string>>>> rows = {
        {"BRAM_18K", {{u.bram18k_pct, kPalette[0]}}},
        {"LUT", {{u.lut_pct, kPalette[1]}}},
        {"FF", {{u.ff_pct, kPalette[2]}}},
        {"DSP", {{u.dsp_pct, kPalette[4]}}}};
    o << "<div class=\"plots\">"
      << svg_bars(id + "-res",
                  std::string("resources (estimate: ") + res::flavour_name(s.resources.flavour) + ") on " +
                      s.device->name + (u.fits ? " (fits)" : " (does not fit)"),
                  rows, {}, 100.0, "% of the device")
      << "</div><table class=\"kv\"><tr><th "
         "class=\"s\">stage</th><th>BRAM_18K</th><th>LUT</th><th>FF</th><th>DSP</th></tr>";
    for (const auto& st : s.resources.stages)
      o << "<tr><td class=\"s\">" << st.stage << "</td><td>" << st.usage.bram18k << "</td><td>" << st.usage.lut
        << "</td><td>" << st.usage.ff << "</td><td>" << st.usage.dsp << "</td></tr>";
    o << "</table>";
  }
  if (!s.synthesis.empty()) {
    o << "<h4>Model and synthesis</h4><table class=\"kv synthesis\"><tr><th class=\"s\">figure</th><th>model</th>"
         "<th>synthesis</th><th>synthesis / model</th><th class=\"s\">note</th></tr>";
    for (const auto& row : s.synthesis) {
      const bool both = row.model > 0 && row.synthesis >= 0;
      o << "<tr><td class=\"s\">" << html_escape(row.figure) << "</td><td>"
        << (row.model >= 0 ? number(row.model) : "-") << "</td><td>"
        << (row.synthesis >= 0 ? number(row.synthesis) : "-") << "</td><td>"
        << (both ? number(row.synthesis / row.model) : "-") << "</td><td class=\"s\">" << html_escape(row.note)
        << "</td></tr>";
    }
    o << "</table>";
  }
  {
    const std::vector<uchar> yaml(s.config_yaml.begin(), s.config_yaml.end());
    o << "<h4>Configuration</h4><p><a download=\"" << html_escape(s.config_file.empty() ? "design.yaml" : s.config_file)
      << "\" href=\"data:text/yaml;base64," << base64(yaml) << "\">save as "
      << html_escape(s.config_file.empty() ? "design.yaml" : s.config_file) << "</a></p><pre>"
      << html_escape(s.config_yaml) << "</pre>";
  }
  if (!s.command.empty()) o << "<p>Reproduce:</p><pre>" << html_escape(s.command) << "</pre>";
  o << "</section>";
  return o.str();
}

std::string standalone_page(const std::string& title, const std::string& body) {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + html_escape(title) +
         "</title><style>" + kStyle + "</style></head><body>" + body + "<script>" + kScript +
         "</script></body></html>\n";
}

namespace {

// The axes a report shows: the sweep's own, or, for a store whose specification lists none (an
// older store, a hand-made one), the paper's structural knobs.
std::vector<std::pair<std::string, std::vector<std::string>>> swept_axes(const SweepSpec& spec) {
  if (!spec.axes.empty()) return spec.axes;
  std::vector<std::pair<std::string, std::vector<std::string>>> fallback;
  for (const char* k : {"paths", "disparities", "parallel_units", "cost", "p1", "p2", "median"})
    fallback.emplace_back(k, std::vector<std::string>{});
  return fallback;
}

bool all_numeric(const std::vector<std::string>& values) {
  for (const auto& v : values) {
    char* end = nullptr;
    std::strtod(v.c_str(), &end);
    if (v.empty() || end == v.c_str() || *end != '\0') return false;
  }
  return true;
}

}  // namespace

std::vector<ResultStore::Row> report_sections(const SweepSpec& spec, const std::vector<ResultStore::Row>& rows,
                                              int details) {
  std::vector<ResultStore::Row> front = pareto_front(spec, rows);
  if (int(front.size()) > details) front.resize(std::size_t(std::max(details, 0)));
  return front;
}

std::string html_report(const SweepSpec& spec, const std::vector<ResultStore::Row>& rows, const ReportOptions& opt) {
  const auto front = pareto_front(spec, rows);
  std::set<std::string> on_front;
  for (const auto& r : front) on_front.insert(r.hash);
  int ok = 0, invalid = 0, failed = 0, meets = 0;
  for (const auto& r : rows) {
    ok += r.status == "ok";
    invalid += r.status == "invalid";
    failed += r.status == "error";
    meets += meets_constraints(spec, r) ? 1 : 0;
  }
  std::ostringstream o;
  o << "<h1>Parallax sweep report: " << html_escape(spec.name)
    << "</h1><section id=\"summary\"><h2>Summary</h2><table class=\"kv\">"
    << "<tr><td>base design</td><td>" << html_escape(spec.base) << "</td></tr><tr><td>strategy</td><td>"
    << spec.strategy << "</td></tr><tr><td>designs</td><td>" << rows.size() << " (" << ok << " evaluated, " << invalid
    << " invalid, " << failed << " failed)</td></tr><tr><td>constraints</td><td>"
    << (spec.require_fit ? "fits " + spec.device : "none")
    << (spec.min_fps > 0 ? ", fps &ge; " + number(spec.min_fps) : "")
    << (spec.max_latency_ms > 0 ? ", latency &le; " + number(spec.max_latency_ms) + " ms" : "") << "</td></tr>"
    << "<tr><td>meet them</td><td>" << meets << "</td></tr><tr><td>objectives</td><td>";
  for (const auto& ob : spec.objectives) o << (ob.maximise ? "max " : "min ") << ob.key << " ";
  o << "</td></tr><tr><td>on the Pareto front</td><td>" << front.size() << "</td></tr>";
  for (const auto& peer : opt.peers) {
    const int beat = beaten_on_accuracy_by(peer, front);
    const double pc = metric(peer, "correct_3px_pct"), pd = metric(peer, "density_pct");
    o << "<tr><td>peer " << html_escape(peer_name(peer)) << "</td><td>correct " << number(std::round(pc * 100) / 100)
      << " %, density " << number(std::round(pd * 100) / 100) << " % on the same frames; beaten on both by " << beat
      << " front design(s)</td></tr>";
  }
  o << "</table></section>";
  // Plots.
  auto pts = [&](const std::string& xk, const std::string& yk, bool x_field) {
    std::vector<Point> p;
    for (const auto& r : rows) {
      if (r.status != "ok") continue;
      const std::string xs = xk == "paths" ? path_count(field(r, xk)) : field(r, xk);
      const double x = x_field ? std::atof(xs.c_str()) : metric(r, xk);
      p.push_back({x, metric(r, yk), "paths " + path_count(field(r, "paths")), field(r, "cost"),
                   r.hash + " " + field(r, "name"), on_front.count(r.hash) > 0, ""});
      if (!opt.seed_hash.empty() && r.hash == opt.seed_hash) {  // the seed again, marked on top
        p.push_back(p.back());
        p.back().tag = "seed";
      }
    }
    if (!x_field)
      for (const auto& peer : opt.peers) {  // only where the peer has both figures (no BRAM, no latency)
        const std::string name = peer_name(peer);
        p.push_back({metric(peer, xk), metric(peer, yk), "", "", name + " (same frames)", false, name});
      }
    return p;
  };
  o << "<section id=\"pareto\"><h2>Pareto plots</h2><div class=\"plots\">"
    << svg_scatter("pareto-bram", "correct vs BRAM", "BRAM_18K", "correct_3px_pct",
                   pts("bram18k", "correct_3px_pct", false))
    << svg_scatter("pareto-latency", "correct vs latency", "latency_ms", "correct_3px_pct",
                   pts("latency_ms", "correct_3px_pct", false))
    << svg_scatter("pareto-density", "density vs correct", "correct_3px_pct", "density_pct",
                   pts("correct_3px_pct", "density_pct", false))
    << "</div></section><section id=\"sensitivity\"><h2>Sensitivity</h2><div class=\"plots\">";
  // One plot per swept axis, in the sweep's order: numbers on a numeric axis, paths by their
  // count, any other value (cost, census, window) by its rank among the values the designs hold
  // (as the stored configurations write them), in order of appearance.
  for (const auto& axis : swept_axes(spec)) {
    const std::string& key = axis.first;
    std::vector<Point> p = pts(key, "correct_3px_pct", true);
    std::string xlabel = key;
    std::vector<std::string> values;
    for (const auto& r : rows)
      if (r.status == "ok" && std::find(values.begin(), values.end(), field(r, key)) == values.end())
        values.push_back(field(r, key));
    if (key != "paths" && !all_numeric(values)) {
      std::size_t i = 0;
      for (const auto& r : rows) {
        if (r.status != "ok") continue;
        p[i++].x = double(std::find(values.begin(), values.end(), field(r, key)) - values.begin());
      }
      xlabel += " (";
      for (std::size_t k = 0; k < values.size(); ++k) xlabel += (k ? ", " : "") + std::to_string(k) + " = " + values[k];
      xlabel += ")";
    }
    o << svg_scatter("sens-" + key, "correct vs " + key, xlabel, "correct_3px_pct", p);
  }
  o << "</div></section>";
  // Table: the swept fields, in the sweep's order.
  std::vector<std::string> shown_cfg;
  for (const auto& axis : swept_axes(spec)) shown_cfg.push_back(axis.first);
  const std::vector<std::string> shown_met = {"correct_3px_pct", "density_pct", "d1_all_pct", "fps", "latency_ms",
                                              "bram18k",         "lut",         "ff",         "dsp", "power_w"};
  o << "<section id=\"table\"><h2>All designs</h2><input id=\"filter\" placeholder=\"filter rows (any text)\"><div "
       "class=\"scroll\">"
    << "<table id=\"designs\"><thead><tr><th class=\"s\">hash</th><th class=\"s\">status</th>";
  for (const auto& c : shown_cfg) o << "<th>" << c << "</th>";
  for (const auto& c : shown_met) o << "<th>" << c << "</th>";
  o << "<th class=\"s\">reason</th></tr></thead><tbody>";
  for (const auto& r : rows) {
    o << "<tr" << (on_front.count(r.hash) ? " class=\"front\"" : "") << "><td class=\"s\">" << r.hash
      << "</td><td class=\"s\">" << r.status << "</td>";
    for (const auto& c : shown_cfg) o << "<td>" << html_escape(field(r, c)) << "</td>";
    for (const auto& c : shown_met) {
      const double v = metric(r, c);
      o << "<td>" << (std::isnan(v) ? "" : number(std::round(v * 100) / 100)) << "</td>";
    }
    o << "<td class=\"s reason\" title=\"" << html_escape(r.reason) << "\">" << html_escape(r.reason) << "</td></tr>";
  }
  o << "</tbody></table></div><p>Rows on the Pareto front are highlighted. CSV and JSON of the same data: "
       "<code>parallax report --db ... --csv designs.csv --json designs.json</code>.</p></section>";
  // Per-design sections for the front.
  o << "<section id=\"designs-detail\"><h2>Designs on the front</h2>";
  int shown = 0;
  for (const auto& r : front) {
    if (shown++ >= opt.details) break;
    DesignSection s;
    s.title = r.hash + ": " + field(r, "name");
    s.config_yaml = r.config_yaml;
    s.metrics = r.metrics;
    s.config_file = "design-" + r.hash + ".yaml";
    s.command = "parallax sweep --base " + s.config_file + " --dataset " +
                (opt.dataset.empty() ? "DATASET" : opt.dataset) + " --frames '" + spec.frames + "' --gt " + spec.gt +
                " --db check.db   # accuracy, timing and resources as stored\n"
                "parallax sim --config " +
                s.config_file + " --device " + spec.device + " --html " + r.hash + ".html";
    const auto it = opt.sections.find(r.hash);
    if (it != opt.sections.end()) {
      const DesignResult& d = it->second;
      if (d.status != "ok") s.title += " (" + d.reason + ")";
      add_figures(s, d);
      if (d.frame_view) add_frame_images(s, *d.frame_view);
      if (d.flight_view) add_flight(s, *d.flight_view);
    }
    o << design_section_html(s);
  }
  if (front.empty()) o << "<p>No design meets the constraints.</p>";
  o << "</section>";
  return standalone_page("Parallax report: " + spec.name, o.str());
}

namespace {

namespace fs = std::filesystem;

// The path as it would be opened: absolute, symbolic links of its existing part resolved.
fs::path resolved(const std::string& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  if (ec) return fs::path(p).lexically_normal();
  const fs::path c = fs::weakly_canonical(a, ec);
  return (ec ? a : c).lexically_normal();
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec) && !ec;
  return resolved(a) == resolved(b);
}

bool inside(const fs::path& p, const fs::path& dir) {
  auto d = dir.begin(), q = p.begin();
  for (; d != dir.end(); ++d, ++q) {
    if (d->empty() && std::next(d) == dir.end()) break;  // a trailing separator
    if (q == p.end() || *q != *d) return false;
  }
  return true;
}

}  // namespace

void check_report_outputs(const std::string& store_path, const std::vector<std::string>& dataset_dirs,
                          const std::vector<std::pair<std::string, std::string>>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const std::string& opt = outputs[i].first;
    const std::string& out = outputs[i].second;
    if (out.empty()) continue;
    for (const char* suffix : {"", "-journal", "-wal", "-shm"})
      if (same_file(out, store_path + suffix))
        throw InputError(opt + " " + out + ": that is the results store the report reads (" + store_path +
                         "); write the report to another file");
    for (const auto& d : dataset_dirs)
      if (!d.empty() && (same_file(out, d) || inside(resolved(out), resolved(d))))
        throw InputError(opt + " " + out + ": inside the dataset folder " + d + "; write the report elsewhere");
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].second.empty() && same_file(out, outputs[j].second))
        throw InputError(opt + " " + out + ": the same file as " + outputs[j].first +
                         "; give each output its own file");
  }
}

std::string images_dataset(const std::string& swept) {
  if (swept.empty()) return "";
  std::error_code ec;
  if (fs::is_directory(swept, ec)) return swept;
  std::fprintf(stderr, "parallax: note: the sweep's dataset %s is gone: no images in the report (give --dataset)\n",
               swept.c_str());
  return "";
}

}  // namespace parallax::reports
