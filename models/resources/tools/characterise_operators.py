#!/usr/bin/env python3
"""Characterise the datapath operators the kernels declare by technology mapping (issue 42).

For every operator kind the kernels' declarations use (kern::OpKind in
kernels/include/parallax/kernels/resources.hpp: adders, comparators, compare-selects, N:1 muxes,
write decoders, bitwise logic, popcounts, multipliers on DSP slices and in fabric (`mul_fabric`,
mapped with -nodsp -abc9), registers, shift registers), at the widths and fan-ins of the grid
below, this script writes a small Verilog module, maps it onto the UltraScale+ primitives with
Yosys (`synth_xilinx -family xcup`, no I/O buffers, no clock buffer, `-widemux 4`: muxes of 4
inputs or more onto LUTs and MUXF7/F8/F9 by cover, as Vivado builds them; without it Yosys 0.23
maps some non-power-of-two muxes through chains of route-through LUTs, a 6:1 byte mux at 64 LUTs)
and records the cells it used. The output, models/data/operators.csv, is committed; rerunning the
script on the same Yosys rewrites it byte for byte.

The grid covers the kernels' range: widths 1-64 bits (the SGM path costs are 5-16 bits, the
aggregated costs up to 22, census codes up to 64), mux fan-ins 2-64 (a register file of D entries
read at a run-time index: D up to 256 is priced by composing 64:1 muxes), shift registers 2-256 deep.

Each combinational operator is measured without registers (FF 0); `register` is W flip-flops
alone; `srl` is a shift register of one bit, `fan_in` deep, with a clock enable (its width
multiplies). Yosys 0.23 maps carry chains to CARRY4 (4 bits each); `carry8` is the UltraScale+
CARRY8 count the same chain needs, ceil(carry4 / 2).

Usage: characterise_operators.py [--out FILE] [--jobs N] [--only KIND[,KIND...]] [--sample N]
  --sample N  characterise only every N-th row of the grid and print the rows (tests)
"""

import argparse
import concurrent.futures
import json
import os
import re
import subprocess
import sys
import tempfile

COLUMNS = ["kind", "width_bits", "fan_in", "b_bits", "lut", "ff", "carry4", "carry8", "srl", "muxf", "dsp", "lutram"]

WIDTHS = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 16, 18, 20, 22, 24, 28, 32, 40, 48, 64]
MUX_FAN_INS = [2, 3, 4, 5, 6, 8, 10, 12, 16, 20, 24, 32, 48, 64]
MUX_WIDTHS = [1, 4, 7, 8, 9, 16]
DECODER_FAN_INS = [2, 4, 6, 8, 10, 16, 32, 64]
POPCOUNT_WIDTHS = [8, 9, 16, 24, 25, 32, 48, 49, 63, 64]
MUL_SHAPES = [(8, 8), (10, 10), (12, 12), (16, 8), (16, 16), (18, 18), (24, 16), (27, 18), (32, 16), (32, 32)]
# Multipliers kept out of DSP slices (BIND_OP impl=fabric, or below the binding threshold): mapped
# with -nodsp -abc9, so LUTs and carries only (Yosys 0.23's default mapper builds these as trees of
# MUXF-fed partial products, 8 x 8 bits in 158 LUT and 80 MUXF; ABC9 in 105 LUT).
MUL_FABRIC_SHAPES = [(3, 3), (4, 4), (6, 6), (8, 4), (8, 8), (10, 10), (12, 8), (12, 12), (16, 8), (16, 16)]
SRL_DEPTHS = [2, 3, 4, 8, 16, 17, 32, 33, 64, 128, 256]


def clog2(n):
    b = 0
    while (1 << b) < n:
        b += 1
    return max(b, 1)


def module(kind, w, n, b):
    """Verilog of one operator: module op, inputs and outputs as ports."""
    if kind == "add":
        return f"module op(input [{w-1}:0] a, input [{w-1}:0] b, output [{w-1}:0] y); assign y = a + b; endmodule"
    if kind == "compare":
        return f"module op(input [{w-1}:0] a, input [{w-1}:0] b, output y); assign y = a < b; endmodule"
    if kind == "equal":
        return f"module op(input [{w-1}:0] a, input [{w-1}:0] b, output y); assign y = a == b; endmodule"
    if kind == "min2":
        return (f"module op(input [{w-1}:0] a, input [{w-1}:0] b, output [{w-1}:0] y); "
                f"assign y = a < b ? a : b; endmodule")
    if kind == "xor":
        return f"module op(input [{w-1}:0] a, input [{w-1}:0] b, output [{w-1}:0] y); assign y = a ^ b; endmodule"
    if kind == "mux":  # an index past N - 1 never happens: those inputs are don't-care, as in HLS
        s = clog2(n)
        return (f"module op(input [{n*w-1}:0] d, input [{s-1}:0] s, output [{w-1}:0] y); "
                f"wire [{w-1}:0] m [0:{(1 << s) - 1}]; genvar k; generate "
                f"for (k = 0; k < {1 << s}; k = k + 1) begin : e "
                f"assign m[k] = k < {n} ? d[k*{w} +: {w}] : {{{w}{{1'bx}}}}; end endgenerate "
                f"assign y = m[s]; endmodule")
    if kind == "decoder":  # a write decoder: the N enables of an N-entry register file from an index
        s = clog2(n)
        return (f"module op(input [{s-1}:0] s, input we, output [{n-1}:0] y); genvar k; generate "
                f"for (k = 0; k < {n}; k = k + 1) begin : e assign y[k] = we && s == k; end endgenerate endmodule")
    if kind == "popcount":
        ob = clog2(w + 1)
        return (f"module op(input [{w-1}:0] a, output reg [{ob-1}:0] y); integer k; always @* begin y = 0; "
                f"for (k = 0; k < {w}; k = k + 1) y = y + a[k]; end endmodule")
    if kind in ("mul", "mul_fabric"):
        return (f"module op(input [{w-1}:0] a, input [{b-1}:0] b, output [{w+b-1}:0] y); "
                f"assign y = a * b; endmodule")
    if kind == "register":
        return (f"module op(input clk, input ce, input [{w-1}:0] d, output reg [{w-1}:0] q); "
                f"always @(posedge clk) if (ce) q <= d; endmodule")
    if kind == "srl":
        return (f"module op(input clk, input ce, input d, output q); reg [{n-1}:0] r; "
                f"always @(posedge clk) if (ce) r <= {{r[{n-2 if n > 1 else 0}:0], d}}; assign q = r[{n-1}]; endmodule")
    raise ValueError(kind)


def grid():
    rows = []
    for kind in ["add", "compare", "equal", "min2", "xor", "register"]:
        rows += [(kind, w, 1, 0) for w in WIDTHS]
    rows += [("mux", w, n, 0) for w in MUX_WIDTHS for n in MUX_FAN_INS]
    rows += [("decoder", 1, n, 0) for n in DECODER_FAN_INS]
    rows += [("popcount", w, 1, 0) for w in POPCOUNT_WIDTHS]
    rows += [("mul", a, 1, b) for a, b in MUL_SHAPES]
    rows += [("mul_fabric", a, 1, b) for a, b in MUL_FABRIC_SHAPES]
    rows += [("srl", 1, n, 0) for n in SRL_DEPTHS]
    return rows


def yosys_version():
    out = subprocess.run(["yosys", "-V"], check=True, capture_output=True, text=True).stdout.strip()
    m = re.match(r"Yosys (\S+)", out)
    return m.group(1) if m else out


def characterise(row):
    kind, w, n, b = row
    with tempfile.TemporaryDirectory(prefix="parallax-op-") as d:
        src = os.path.join(d, "op.v")
        stat = os.path.join(d, "stat.json")
        with open(src, "w") as f:
            f.write(module(kind, w, n, b) + "\n")
        nodsp = " -nodsp -abc9" if kind == "mul_fabric" else ""
        script = (f"read_verilog {src}; synth_xilinx -family xcup -top op -flatten -noiopad -noclkbuf -widemux 4{nodsp}; "
                  f"tee -q -o {stat} stat -json")
        r = subprocess.run(["yosys", "-q", "-p", script], capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"yosys failed on {row}: {r.stderr.strip() or r.stdout.strip()}")
        with open(stat) as f:
            cells = json.load(f)["design"]["num_cells_by_type"]
    count = lambda pred: sum(v for k, v in cells.items() if pred(k))
    carry4 = count(lambda k: k == "CARRY4")
    return {
        "kind": kind, "width_bits": w, "fan_in": n, "b_bits": b,
        "lut": count(lambda k: re.fullmatch(r"LUT[1-6]", k) is not None),
        "ff": count(lambda k: k in ("FDRE", "FDSE", "FDCE", "FDPE")),
        "carry4": carry4, "carry8": (carry4 + 1) // 2 + count(lambda k: k == "CARRY8"),
        "srl": count(lambda k: k.startswith("SRL")),
        "muxf": count(lambda k: k.startswith("MUXF")),
        "dsp": count(lambda k: k.startswith("DSP48")),
        "lutram": count(lambda k: k.startswith("RAM") and not k.startswith("RAMB")),
    }


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.normpath(os.path.join(here, "..", "..", "data", "operators.csv")),
                    help="the table to write (default: models/data/operators.csv, the committed one)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="Yosys runs in parallel (default: the machine's cores)")
    ap.add_argument("--only", default="", help="comma-separated kinds")
    ap.add_argument("--sample", type=int, default=0, help="every N-th row only; print instead of writing")
    a = ap.parse_args()
    if a.jobs < 1 or a.sample < 0:
        sys.exit("characterise_operators: --jobs must be at least 1 and --sample at least 0")
    try:
        version = yosys_version()
    except (OSError, subprocess.CalledProcessError) as e:
        sys.exit(f"characterise_operators: yosys is not installed or does not run ({e}); apt-get install yosys")
    rows = grid()
    if a.only:
        kinds = set(a.only.split(","))
        unknown = kinds - {r[0] for r in rows}
        if unknown:
            sys.exit(f"characterise_operators: --only: unknown kind(s) {', '.join(sorted(unknown))}")
        rows = [r for r in rows if r[0] in kinds]
    if a.sample > 0:
        rows = rows[:: a.sample]
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        for i, res in enumerate(ex.map(characterise, rows)):
            results.append(res)
            if a.sample == 0 and (i + 1) % 25 == 0:
                print(f"characterise_operators: {i + 1}/{len(rows)} operators mapped", file=sys.stderr)
    lines = ["# Operators mapped onto UltraScale+ primitives by Yosys " + version +
             " (synth_xilinx -family xcup -flatten -noiopad -noclkbuf -widemux 4),",
             "# written by models/resources/tools/characterise_operators.py (issue 42); rerun it rather than edit.",
             "# kind, width_bits, fan_in (mux inputs, decoder outputs, srl depth), b_bits (multiplier's second operand);",
             "# cells: LUT1-6, FDxE flip-flops, CARRY4 (Yosys " + version + " maps carries to CARRY4) and the CARRY8",
             "# the chain needs on UltraScale+, SRL16E/SRLC32E, MUXF7/F8, DSP48E2, LUTRAM.",
             ",".join(COLUMNS)]
    lines += [",".join(str(r[c]) for c in COLUMNS) for r in results]
    text = "\n".join(lines) + "\n"
    if a.sample > 0:
        sys.stdout.write(text)
        return
    try:
        with open(a.out, "w") as f:
            f.write(text)
    except OSError as e:
        sys.exit(f"characterise_operators: {a.out}: cannot write ({e.strerror})")
    print(f"characterise_operators: wrote {len(results)} operators to {a.out} (Yosys {version})", file=sys.stderr)


if __name__ == "__main__":
    main()
