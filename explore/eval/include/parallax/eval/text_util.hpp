// Small text helpers shared by the explorer's sources (not part of the public headers).
#pragma once

#include <cctype>
#include <cstdio>
#include <ctime>
#include <string>

namespace parallax::eval::detail {

// s without leading and trailing white space.
inline std::string trim(const std::string& s) {
  std::size_t b = 0;
  std::size_t e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b])) != 0) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1])) != 0) --e;
  return s.substr(b, e - b);
}

// The current time as ISO 8601 UTC, e.g. 2026-11-30T17:23:34Z (the results store's timestamps).
inline std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace parallax::eval::detail
