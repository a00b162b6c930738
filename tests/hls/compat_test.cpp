// The compat/ stand-ins of the vendor headers, on which `make csim` without Vitis relies:
// ap_uint/ap_int wrap to their width as the vendor's types do; hls::stream is a FIFO whose misuse
// (reading an empty stream, tokens left at the end) stops the C simulation with the stream's name.
#include <gtest/gtest.h>

#include <ap_axi_sdata.h>
#include <ap_int.h>
#include <hls_stream.h>

namespace {

TEST(CompatApInt, UnsignedWrapsToItsWidth) {
  const ap_uint<6> a = 70;  // 70 mod 64
  EXPECT_EQ(a.to_uint(), 6u);
  const ap_uint<6> m = -1;
  EXPECT_EQ(m.to_uint(), 63u);
  const ap_uint<64> w = ~0ull;
  EXPECT_EQ(w.to_uint64(), ~0ull);
  const ap_uint<1> bit = 3;
  EXPECT_EQ(bit.to_uint(), 1u);
  EXPECT_EQ(ap_uint<13>::length(), 13);
  const ap_uint<4> narrow = ap_uint<8>(0xAB);  // width conversion keeps the low bits
  EXPECT_EQ(narrow.to_uint(), 0xBu);
  unsigned long long implicit = ap_uint<10>(1023);
  EXPECT_EQ(implicit, 1023ull);
}

TEST(CompatApInt, SignedWrapsInTwosComplement) {
  EXPECT_EQ(ap_int<4>(9).to_int(), -7);
  EXPECT_EQ(ap_int<4>(-8).to_int(), -8);
  EXPECT_EQ(ap_int<4>(7).to_int(), 7);
  EXPECT_EQ(ap_int<32>(-5).to_int64(), -5);
  EXPECT_EQ(ap_int<64>(-1ll).to_int64(), -1);
}

TEST(CompatAxis, SideChannelWidths) {
  ap_axiu<16, 1, 1, 1> beat;
  beat.data = 0x1FFFF;  // 17 bits into 16
  beat.keep = -1;
  beat.last = 2;
  EXPECT_EQ(beat.data.to_uint(), 0xFFFFu);
  EXPECT_EQ(beat.keep.to_uint(), 0x3u);  // one bit per byte
  EXPECT_EQ(beat.last.to_uint(), 0u);
}

TEST(CompatStream, FirstInFirstOut) {
  hls::stream<int> s("fifo");
  EXPECT_TRUE(s.empty());
  s.write(1);
  s << 2;
  EXPECT_EQ(s.size(), 2u);
  EXPECT_FALSE(s.full());
  int v = 0;
  s >> v;
  EXPECT_EQ(v, 1);
  EXPECT_TRUE(s.read_nb(v));
  EXPECT_EQ(v, 2);
  EXPECT_FALSE(s.read_nb(v));
  EXPECT_TRUE(s.empty());
}

TEST(CompatStreamDeathTest, ReadingAnEmptyStreamStopsNamingIt) {
  EXPECT_DEATH(
      {
        hls::stream<int> s("cost");
        (void)s.read();
      },
      "hls::stream 'cost': read while empty");
}

TEST(CompatStreamDeathTest, TokensLeftAtTheEndStopNamingTheStream) {
  EXPECT_DEATH(
      {
        hls::stream<int> s("sum");
        s.write(3);
      },
      "hls::stream 'sum': 1 token\\(s\\) left unread");
}

}  // namespace
