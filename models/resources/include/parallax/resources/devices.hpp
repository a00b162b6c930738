// FPGA device totals (BRAM_18K, URAM, DSP, FF, LUT), read from models/data/devices.yaml,
// which is compiled into the library (no file is opened at run time).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace parallax::res {

struct Device {
  std::string name, family, source;  // family: zynq-ultrascale+ | zynq-7000
  int64_t bram18k = 0, uram = 0, dsp = 0, ff = 0, lut = 0;
};

// All devices in file order, parsed once from the embedded YAML. A malformed embedded file is
// a programming error: std::logic_error naming the device and the field.
const std::vector<Device>& devices();

// Case-insensitive lookup; nullptr if unknown.
const Device* find_device(const std::string& name);

// "XCZU3EG, XCZU5EV, ..." (file order), for error messages.
std::string device_names();

// The parser behind devices(), exposed for tests: a list of maps with exactly the fields
// name, family, bram18k, uram, dsp, ff, lut, source; counts are integers >= 0; names unique
// (case-insensitive). Throws std::logic_error naming the offending field.
std::vector<Device> parse_devices(const std::string& yaml_text);

}  // namespace parallax::res
