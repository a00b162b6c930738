// Compiled as C++14 without exceptions or RTTI: proves every kernel header stays within the
// synthesisable subset's language level.
#include "parallax/kernels/caps.hpp"
#include "parallax/kernels/census.hpp"
#include "parallax/kernels/frame_buffer.hpp"
#include "parallax/kernels/median.hpp"
#include "parallax/kernels/rectify.hpp"
#include "parallax/kernels/resources.hpp"
#include "parallax/kernels/sad.hpp"
#include "parallax/kernels/sgm.hpp"
#include "parallax/kernels/wta_lr.hpp"

typedef parallax::kern::Caps<64, 16, 4> TinyCaps;
// Instantiate every stage once so that the whole template bodies are checked.
template class parallax::kern::CostStage<TinyCaps, parallax::kern::CensusMatcher<TinyCaps> >;
template class parallax::kern::CostStage<TinyCaps, parallax::kern::SadMatcher<TinyCaps> >;
template class parallax::kern::SgmAggregate<TinyCaps, uint16_t>;
template class parallax::kern::WtaLr<TinyCaps, uint16_t>;
template class parallax::kern::Median<TinyCaps>;
template class parallax::kern::Rectify<64, 8>;
template class parallax::kern::Rectify<64, 8, true>;
// The frame buffer's packing, at a width of several limbs.
template void parallax::kern::frame_pack(const parallax::kern::Lanes<uint16_t, 4>&,
                                         const parallax::kern::Lanes<uint16_t, 4>&, int, int, int, uint32_t (&)[4]);
template void parallax::kern::frame_unpack(const uint32_t (&)[4], int, int, int, parallax::kern::Lanes<uint16_t, 4>&,
                                           parallax::kern::Lanes<uint16_t, 4>&);
