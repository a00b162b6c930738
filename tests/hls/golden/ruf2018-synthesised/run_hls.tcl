# Design ruf2018-synthesised, exported by `parallax export-hls`: C simulation, synthesis at 5.000 ns
# (200 MHz) for xczu3eg-sbva484-1-e, C/RTL co-simulation, and export as a Vivado IP.
#   vitis_hls -f run_hls.tcl                      (Vitis HLS up to 2024.2; `make vitis FLOW=vitis_hls`)
#   vitis-run --mode hls --tcl run_hls.tcl        (Vitis 2023.2 and later)
# The testbench's data files are copied next to the simulation binaries, hence the argument ".".
#
# Co-simulation runs on the reduced frame by default: the design rebuilt with
# -DPARALLAX_REDUCED_FRAME for the pair's first 16 rows (the size is compile-time, so
# this is a second synthesis, project parallax_ruf2018_synthesised_reduced), checked bit for bit against
# tb/golden_disparity_reduced.pgm. With COSIM_FULL=1 in the environment (`make vitis COSIM_FULL=1`)
# it runs on the synthesised full-frame design instead: same check against tb/golden_disparity.pgm,
# many more cycles of RTL simulation.
set cosim_full [expr {[info exists ::env(COSIM_FULL)] && $::env(COSIM_FULL) eq "1"}]

# One project: the sources, the testbench and its data, the part and the clock. `defines` are
# added to the compiler flags of both the design and the testbench.
proc parallax_project {name defines golden} {
  open_project -reset $name
  set_top parallax_top
  add_files src/parallax_top.cpp -cflags "-std=c++14 -Isrc $defines"
  add_files -tb tb/parallax_tb.cpp -cflags "-std=c++14 -Isrc $defines"
  add_files -tb tb/left.pgm
  add_files -tb tb/right.pgm
  add_files -tb tb/$golden
  add_files -tb tb/map_left.bin
  add_files -tb tb/map_right.bin
  open_solution -reset solution1 -flow_target vivado
  set_part {xczu3eg-sbva484-1-e}
  create_clock -period 5.000 -name default
}

# The full frame: C simulation, synthesis (the report and the IP are this design's).
parallax_project parallax_ruf2018_synthesised "" golden_disparity.pgm
csim_design -argv {.}
csynth_design
if {$cosim_full} {
  cosim_design -argv {.}
}
export_design -format ip_catalog
close_project

# The reduced frame: synthesis and C/RTL co-simulation.
if {!$cosim_full} {
  parallax_project parallax_ruf2018_synthesised_reduced "-DPARALLAX_REDUCED_FRAME" golden_disparity_reduced.pgm
  csynth_design
  cosim_design -argv {.}
  close_project
}
exit
