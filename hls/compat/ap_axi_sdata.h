// Parallax's stand-in for the Vitis HLS header of the same name (see ap_int.h here): the side
// channels of one AXI4-Stream beat. TDATA is WData bits; TKEEP/TSTRB one bit per byte; TUSER,
// TID and TDEST as wide as given (at least one bit, as in every Vitis release); TLAST one bit.
// ap_int.h comes from the include path, not from this folder: built against the vendor's
// ap_int.h (`make csim HLS_INCLUDE=DIR`, this folder only behind DIR), a quoted include would
// pull in the stand-in beside the vendor's and define ap_uint twice.
#pragma once

#include <ap_int.h>

template <int WData, int WUser, int WId, int WDest>
struct ap_axiu {
  ap_uint<WData> data;
  ap_uint<(WData + 7) / 8> keep;
  ap_uint<(WData + 7) / 8> strb;
  ap_uint<WUser> user;
  ap_uint<1> last;
  ap_uint<WId> id;
  ap_uint<WDest> dest;
};
