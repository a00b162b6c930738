// Text helpers of the HTML and CSV writers (reports/src): numbers as the reports print them and
// HTML escaping.
#pragma once

#include <cmath>
#include <sstream>
#include <string>

namespace parallax::reports {

// Up to 10 significant digits; NaN prints as empty (a missing figure).
inline std::string number(double v) {
  if (std::isnan(v)) return "";
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

// Escapes <, >, & and " for element text and attribute values.
inline std::string html_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else if (c == '"')
      o += "&quot;";
    else
      o += c;
  }
  return o;
}

}  // namespace parallax::reports
