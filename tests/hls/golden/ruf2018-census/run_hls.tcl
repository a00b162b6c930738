# Design ruf2018-census, exported by `parallax export-hls`: C simulation, synthesis at 5.000 ns
# (200 MHz) for xczu3eg-sbva484-1-e, C/RTL co-simulation, and export as a Vivado IP.
#   vitis_hls -f run_hls.tcl                      (Vitis HLS up to 2024.2)
#   vitis-run --mode hls --tcl run_hls.tcl        (Vitis 2023.2 and later)
# The testbench's data files are copied next to the simulation binaries, hence the argument ".".
open_project -reset parallax_ruf2018_census
set_top parallax_top
add_files src/parallax_top.cpp -cflags "-std=c++14 -Isrc"
add_files -tb tb/parallax_tb.cpp -cflags "-std=c++14 -Isrc"
add_files -tb tb/left.pgm
add_files -tb tb/right.pgm
add_files -tb tb/golden_disparity.pgm
open_solution -reset solution1 -flow_target vivado
set_part {xczu3eg-sbva484-1-e}
create_clock -period 5.000 -name default
csim_design -argv {.}
csynth_design
cosim_design -argv {.}
export_design -format ip_catalog
exit
