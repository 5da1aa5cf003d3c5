# Turns a `hlod play` CSV (player/stats.h columns, '#' comment lines) into a space-separated
# table with a header for gnuplot: the plotted columns, percent differences of the estimates
# (thesis Fig. 6.4: 100 (actual - estimate) / estimate, negative = conservative estimate),
# 35-frame moving averages (Fig. 6.4d, 6.6), memory in MiB and, as the thesis draws it, in
# percent of the memory budget (`# memory_budget_bytes:` preamble line; c_memory x cost, and the
# real bytes beside it; 0 without a budget) (Fig. 6.1), the hlod0 share, and per-level shares of
# nodes and triangles (Fig. 6.2/6.3). Every field but `policy` (a name) must be a number.
# Errors: one line naming the file, exit 2.
function fail(msg) { print name ": " msg > "/dev/stderr"; failed = 1; exit 2 }
function pct(actual, estimate) { return estimate > 0 ? 100 * (actual - estimate) / estimate : 0 }
function col(c) { return $(idx[c]) }
/^# memory_budget_bytes:/ { budget = $0; sub(/^# memory_budget_bytes: */, "", budget); budget += 0 }
/^#/ { next }
header == 0 {
    header = 1
    for (i = 1; i <= NF; i++) idx[$i] = i
    policyCol = ("policy" in idx) ? idx["policy"] : 0
    n = split("frame time_s target_ms est_nofb_ms est_ms actual_ms v_time hlod0_share_ms up_toggles down_toggles resident_bytes memory_estimate_bytes nodes_drawn tris_drawn", need, " ")
    for (k = 1; k <= n; k++) if (!(need[k] in idx)) fail("no column '" need[k] "' (not a hlod play statistics log?)")
    levels = 0
    while (("nodes_l" levels) in idx && ("tris_l" levels) in idx) levels++
    if (levels == 0) fail("no per-level columns nodes_l0.. / tris_l0..")
    printf "frame time_s target_ms actual_ms est_ms est_nofb_ms v_time pct_nofb pct_fb ma_nofb ma_fb up down ma_toggles resident_mib estimate_mib resident_pct estimate_pct share_ms"
    for (l = 0; l < levels; l++) printf " nodes_l%d pnodes_l%d tris_l%d ptris_l%d", l, l, l, l
    printf "\n"
    next
}
{
    if (NF != length(idx)) fail("line " NR ": " NF " fields, header has " length(idx))
    for (i = 1; i <= NF; i++) if (i != policyCol && $i !~ /^-?[0-9.]+([eE][-+]?[0-9]+)?$/ && $i !~ /^-?(nan|inf)$/) fail("line " NR ": field " i " is not a number: '" $i "'")
    rows++
    nofb = pct(col("actual_ms"), col("est_nofb_ms")); fb = pct(col("actual_ms"), col("est_ms"))
    toggles = col("up_toggles") + col("down_toggles")
    slot = rows % 35
    sumNofb += nofb - hNofb[slot]; hNofb[slot] = nofb
    sumFb += fb - hFb[slot]; hFb[slot] = fb
    sumTog += toggles - hTog[slot]; hTog[slot] = toggles
    window = rows < 35 ? rows : 35
    printf "%s %s %s %s %s %s %s %.6g %.6g %.6g %.6g %s %s %.6g %.6g %.6g", col("frame"), col("time_s"), col("target_ms"),
        col("actual_ms"), col("est_ms"), col("est_nofb_ms"), col("v_time"), nofb, fb, sumNofb / window, sumFb / window,
        col("up_toggles"), -col("down_toggles"), sumTog / window, col("resident_bytes") / 1048576, col("memory_estimate_bytes") / 1048576
    printf " %.6g %.6g %s", (budget > 0 ? 100 * col("resident_bytes") / budget : 0),
        (budget > 0 ? 100 * col("memory_estimate_bytes") / budget : 0), col("hlod0_share_ms")
    nodes = col("nodes_drawn"); tris = col("tris_drawn")
    for (l = 0; l < levels; l++) {
        n = col("nodes_l" l); t = col("tris_l" l)
        printf " %s %.6g %s %.6g", n, (nodes > 0 ? 100 * n / nodes : 0), t, (tris > 0 ? 100 * t / tris : 0)
    }
    printf "\n"
}
END {
    if (failed) exit 2
    if (!header) { print name ": empty (no header line)" > "/dev/stderr"; exit 2 }
    if (rows < 2) { print name ": fewer than two frames to plot" > "/dev/stderr"; exit 2 }
}
