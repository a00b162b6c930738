// unit: the device database compiled from models/data/devices.yaml.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "parallax/resources/devices.hpp"

namespace parallax::res {
namespace {

const char* const kAll[] = {"XCZU3EG", "XCZU5EV", "XCZU7EV", "XCZU9EG", "XC7Z020", "XC7Z045"};

TEST(Devices, EveryDevicePresentWithPositiveTotals) {
  EXPECT_EQ(devices().size(), 6u);
  for (const char* name : kAll) {
    const Device* d = find_device(name);
    ASSERT_NE(d, nullptr) << name;
    EXPECT_EQ(d->name, name);
    EXPECT_TRUE(d->family == "zynq-ultrascale+" || d->family == "zynq-7000") << name << ": " << d->family;
    EXPECT_FALSE(d->source.empty()) << name;
    EXPECT_GT(d->bram18k, 0) << name;
    EXPECT_GE(d->uram, 0) << name;
    EXPECT_GT(d->dsp, 0) << name;
    EXPECT_GT(d->ff, 0) << name;
    EXPECT_GT(d->lut, 0) << name;
    EXPECT_EQ(d->ff, 2 * d->lut) << name;  // two flip-flops per LUT in both families
  }
}

TEST(Devices, Xczu3egTotals) {
  const Device* d = find_device("XCZU3EG");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->family, "zynq-ultrascale+");
  EXPECT_EQ(d->bram18k, 432);
  EXPECT_EQ(d->uram, 0);
  EXPECT_EQ(d->dsp, 360);
  EXPECT_EQ(d->ff, 141120);
  EXPECT_EQ(d->lut, 70560);
  EXPECT_NE(d->source.find("DS891"), std::string::npos) << d->source;
}

TEST(Devices, OtherTotals) {
  EXPECT_EQ(find_device("XCZU5EV")->bram18k, 288);  // 144 RAMB36
  EXPECT_EQ(find_device("XCZU5EV")->uram, 64);
  EXPECT_EQ(find_device("XCZU7EV")->bram18k, 624);  // 312 RAMB36
  EXPECT_EQ(find_device("XCZU7EV")->uram, 96);
  EXPECT_EQ(find_device("XCZU9EG")->dsp, 2520);
  EXPECT_EQ(find_device("XC7Z020")->bram18k, 280);
  EXPECT_EQ(find_device("XC7Z020")->family, "zynq-7000");
  EXPECT_EQ(find_device("XC7Z045")->bram18k, 1090);
}

TEST(Devices, LookupIsCaseInsensitive) {
  const Device* lower = find_device("xczu3eg");
  ASSERT_NE(lower, nullptr);
  EXPECT_EQ(lower, find_device("XCZU3EG"));
  EXPECT_EQ(find_device("XcZu3Eg"), lower);
  EXPECT_EQ(lower->name, "XCZU3EG");
}

TEST(Devices, UnknownIsNullptr) {
  EXPECT_EQ(find_device("XCZU99XX"), nullptr);
  EXPECT_EQ(find_device(""), nullptr);
  EXPECT_EQ(find_device("XCZU3"), nullptr);
}

TEST(Devices, NamesListContainsAll) {
  const std::string names = device_names();
  for (const char* name : kAll) EXPECT_NE(names.find(name), std::string::npos) << names;
  EXPECT_EQ(names.rfind("XCZU3EG, XCZU5EV", 0), 0u) << names;
}

// The parser rejects malformed text with the field named (a programming error: logic_error).
void expect_logic_error(const std::string& yaml, const std::string& needle) {
  try {
    parse_devices(yaml);
    ADD_FAILURE() << "accepted:\n" << yaml;
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Devices, MalformedYamlNamesTheField) {
  const std::string ok = "- {name: A, family: zynq-7000, source: s, bram18k: 1, uram: 0, dsp: 1, ff: 2, lut: 1}\n";
  EXPECT_EQ(parse_devices(ok).size(), 1u);
  expect_logic_error("- {name: A, family: zynq-7000, source: s, uram: 0, dsp: 1, ff: 2, lut: 1}\n", "'bram18k'");
  expect_logic_error("- {name: A, family: zynq-7000, source: s, bram18k: x, uram: 0, dsp: 1, ff: 2, lut: 1}\n",
                     "'bram18k'");
  expect_logic_error("- {name: A, family: zynq-7000, source: s, bram18k: 1, uram: -1, dsp: 1, ff: 2, lut: 1}\n",
                     "'uram'");
  expect_logic_error("- {name: A, family: virtex, source: s, bram18k: 1, uram: 0, dsp: 1, ff: 2, lut: 1}\n",
                     "'family'");
  expect_logic_error("- {name: A, family: zynq-7000, source: s, bram18k: 1, uram: 0, dsp: 1, ff: 2, lut: 1, lutt: 3}\n",
                     "'lutt'");
  expect_logic_error(ok + "- {name: a, family: zynq-7000, source: s, bram18k: 1, uram: 0, dsp: 1, ff: 2, lut: 1}\n",
                     "'name'");
  expect_logic_error("name: A\n", "list");
}

}  // namespace
}  // namespace parallax::res
