// Published resource rows in CSV (the columns of ../shared/data/resource-points/points.csv and
// models/data/vitis_vision_points.csv): each row's configuration as variables for a function
// description (functions.hpp) and its published figures.
//
// Columns read (by header name; others are ignored): kernel and design (required), width, height,
// npc, clock_mhz, disparities, parallel_units (also as pu), paths, window, notes, source_detail,
// device, and the
// published bram18k, uram, dsp, ff, lut (an empty cell: not published). Variables of a row:
//   width, height, clock_mhz, disparities, pu, paths   numbers; "not stated" or text: unstated
//   npc                    the leading integer ("8 Pixel (as printed)" is 8); default 1
//   kw, kh, k              from the first "WxH" of window ("5x5 census": 5, 5, 5; k = max)
//   out_width, out_height  from "... TO WxH" in window (resize)
//   NAME (lower case)      from "NAME=N" in window (store_lines, win_rows)
//   channels               3 when kernel, design or notes say 3ch, 3-channel, BGR or channels=3
//   uram                   1 when they or source_detail (the doc's table) say URAM or UltraRAM
//   versal                 1 when the device is a Versal part (xcv...: DSP58 slices)
#pragma once

#include <string>
#include <vector>

#include "parallax/resources/functions.hpp"

namespace parallax::res {

// A published figure, or not published (-1).
struct PublishedUsage {
  int64_t bram18k = -1, uram = -1, dsp = -1, ff = -1, lut = -1;
};

struct CsvPoint {
  int line = 0;  // 1-based line of the row in its file
  std::string kernel, design;
  RowVariables vars;
  PublishedUsage published;
};

// Parses CSV text (RFC 4180: quoted fields, doubled quotes, newlines inside quotes). Throws
// ConfigError naming the file (and line) for a missing required column or a malformed number in
// a published column.
std::vector<CsvPoint> parse_points_csv(const std::string& text, const std::string& file);
std::vector<CsvPoint> load_points_csv(const std::string& path);

}  // namespace parallax::res
