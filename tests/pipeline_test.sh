#!/bin/sh
# The TT Zero pipeline (pipelines/Makefile) on the first 3 km of the Snaefell course, so that CI
# exercises it end to end: course -> road.h5 -> reference lap -> plots with the pipelines' own
# solver (LAP_FLAGS: the indirect solver), a lap of another circuit (tracks), then two-point gear and battery studies by Ipopt (the
# second battery point warm-started from the first), the report of the studies so far, and the
# retries of an Ipopt solve and of an indirect one (by Ipopt).
# Usage: pipeline_test.sh BUILD_DIR SHARED_DATA
set -eu
build=$1 shared=$2
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
run_make() { make --no-print-directory -C "$here/../pipelines" BIN="$build" OUT="$out" SHARED="$shared" PIECE_M=3000 "$@"; }
# The pipelines' Ipopt path (warm starts with NEIGHBOUR_FLAGS, retries): LAP_FLAGS until session 44.
ipopt="--solver ipopt --ds 10"

run_make run
d=$out/snaefell-3000m
for f in road.h5 reference/lap.h5 reference/plots/summary.md reference/plots/speed.png reference/report.md; do
  [ -s "$d/$f" ] || fail "$d/$f missing"
done
grep -q "^converged      yes" "$d/reference/lap.txt" || fail "the reference lap did not converge: $(cat "$d/reference/lap.txt")"
/usr/bin/python3 -c 'import sys, h5py; s = h5py.File(sys.argv[1]).attrs["solver"]; sys.exit((s.decode() if isinstance(s, bytes) else s) != "indirect")' \
  "$d/reference/lap.h5" || fail "the reference lap is not the indirect solver's"

# Another circuit (the tracks target): fitted by road_fit, lapped by the piece's bike (no
# calibration) from a flying start, plotted, and a row of tracks/report.md.
run_make tracks TRACKS=Nuerburgring-centreline-widths > /dev/null 2> "$out/tracks.log" || fail "tracks: $(cat "$out/tracks.log")"
t=$d/tracks/Nuerburgring-centreline-widths
for f in road.h5 lap.h5 plots/map.png plots/summary.md; do [ -s "$t/$f" ] || fail "$t/$f missing"; done
grep -q "^converged      yes" "$t/lap.txt" || fail "the lap of the Nuerburgring did not converge: $(cat "$t/lap.txt")"
grep -q "^| Nuerburgring-centreline-widths | 5\.1[0-9] | 0 | [0-9.]* | 0\.0 | [0-9]:[0-9][0-9]\.[0-9] | .* | flying at [0-9.]* km/h | yes | " "$d/tracks/report.md" ||
  fail "tracks/report.md: $(cat "$d/tracks/report.md")"

# Dry runs (nothing solved): on the whole course the calibration's lap at the fitted value is the
# reference lap unless the calibration solves with other flags.
plan=$(run_make -n run PIECE_M=)
echo "$plan" | grep -q -- "--keep-lap $out/snaefell/reference --" || fail "make run does not keep the calibration's lap"
! echo "$plan" | grep -q "reference/lap-attempt.h5" || fail "make run solves the reference lap again"
plan=$(run_make -n run PIECE_M= CAL_FLAGS="--solver ipopt --ds 20")
echo "$plan" | grep -q "reference/lap-attempt.h5" || fail "with other CAL_FLAGS the reference lap is not solved"
# Every study's point at data/bx15.yaml's own values is the reference lap; the grid's points at
# its pack or gear are the gear or battery study's; the others are solved.
plan=$(run_make -n motors gear battery grid GEARS="2.8 3.0" PACK_MJ="51" GRID_GEARS="2.8 3.0" GRID_MJ="37 51")
for p in motors/2_4 gear/2.8 battery/51 grid/2.8_51; do
  echo "$plan" | grep -q "^cp $d/reference/lap.h5 $d/studies/$p/lap.h5.tmp" || fail "$p is not the reference lap"
done
echo "$plan" | grep -q "^cp $d/studies/gear/3.0/lap.h5 $d/studies/grid/3.0_51/lap.h5.tmp" || fail "grid 3.0_51 is not gear 3.0"
echo "$plan" | grep -q "^cp $d/studies/battery/37/lap.h5 $d/studies/grid/2.8_37/lap.h5.tmp" || fail "grid 2.8_37 is not battery 37"
solved=$(echo "$plan" | grep -o "studies/[a-z]*/[0-9._]*/lap-attempt.h5" | sort -u | tr '\n' ' ')
[ "$solved" = "studies/battery/37/lap-attempt.h5 studies/gear/3.0/lap-attempt.h5 studies/grid/3.0_37/lap-attempt.h5 studies/motors/3_4/lap-attempt.h5 studies/motors/3_5/lap-attempt.h5 " ] ||
  fail "the dry run solves $solved"
# The battery study and the grid are solved from the bike's pack (51 MJ: the reference lap, the
# gear study's points) first, then from the largest pack down.
order=$(run_make -n battery grid PACK_MJ="30 60 51 42" GRID_GEARS="3.0 3.4" GRID_MJ="37 60 51" |
  grep -o "studies/[a-z]*/[0-9._]*/lap-attempt.h5 " | uniq | sed 's|/lap-attempt.h5||' | tr -d '\n')
[ "$order" = "studies/battery/60 studies/battery/42 studies/battery/30 studies/gear/3.0 studies/gear/3.4 \
studies/grid/3.0_60 studies/grid/3.4_60 studies/grid/3.0_37 studies/grid/3.4_37 " ] || fail "the order of the solves: $order"
# QUICK=yes: every point on the quick mesh into studies-quick/, the bike's own points copies of its
# gear point there (not of the reference lap).
plan=$(run_make -n motors grid QUICK=yes GRID_GEARS="2.8 3.0" GRID_MJ="51")
q=$d/studies-quick
for p in motors/2_4 grid/2.8_51; do
  echo "$plan" | grep -q "^cp $q/gear/2.8/lap.h5 $q/$p/lap.h5.tmp" || fail "quick $p is not the quick gear 2.8"
done
solved=$(echo "$plan" | grep -- "--ds 40 --dt-max 1" | grep -o "studies-quick/[a-z]*/[0-9._]*/lap-attempt.h5" | sort -u | wc -l)
[ "$solved" = 4 ] || fail "the quick dry run solves $solved points on the quick mesh, not 4"
! echo "$plan" | grep -q "reference/lap" || fail "the quick studies use the reference lap"

# WARM_START=yes: the gear study starts cold; the battery study from the largest pack down, each
# point after the first from its nearest solved neighbour with NEIGHBOUR_FLAGS (a monotone barrier
# from 1e-4).
run_make gear battery GEARS="3.0 3.4" PACK_MJ="40 45" WARM_START=yes LAP_FLAGS="$ipopt" -j1
for p in gear/3.0 gear/3.4 battery/40 battery/45; do [ -s "$d/studies/$p/lap.h5" ] || fail "$p: no lap.h5"; done
/usr/bin/python3 - "$d/studies" <<'PY'
import sys, h5py
studies = sys.argv[1]
text = lambda v: v.decode() if isinstance(v, bytes) else str(v)
for point, init, strategy in (("gear/3.0", "", "adaptive"), ("gear/3.4", "", "adaptive"),
                              ("battery/45", "", "adaptive"), ("battery/40", "battery/45/lap.h5", "monotone")):
    with h5py.File(f"{studies}/{point}/lap.h5") as lap:
        a = lap.attrs
        assert text(a["init_file"]).endswith(init) and (init or text(a["init_file"]) == ""), (point, dict(a))
        assert text(a["mu_strategy"]) == strategy, (point, dict(a))
        assert strategy == "adaptive" or a["mu_init"] == 1e-4, (point, dict(a))
        print(point, a["lap_time"], "s")
PY
# The grid's warm start is along the pack: the same gear's lap, though another gear's is nearer.
plan=$(run_make -n grid GRID_GEARS="3.0 3.4" GRID_MJ="40" WARM_START=yes LAP_FLAGS="$ipopt")
echo "$plan" | grep -q "nearest_lap.py $d/studies/grid/3.0_40 --along 2" || fail "the grid's warm start: $plan"
# The indirect solver's laps start cold whatever WARM_START says (pipelines/Makefile, WARM).
! run_make -n grid GRID_GEARS="3.0 3.4" GRID_MJ="40" WARM_START=yes | grep -q "nearest_lap.py" ||
  fail "WARM_START=yes warm-starts the indirect solver"
# The report so far: a point not copied yet stands in by the lap it will copy (grid 2.8_51 by the
# reference lap, 3.4_51 by gear 3.4); 2.8_37 and 3.4_37 are not solved.
grid=$(run_make -n report-so-far GRID_GEARS="2.8 3.4" GRID_MJ="37 51" | grep -o -- "--grid [^\\]*")
[ "$grid" = "--grid $d/reference/lap.h5 $d/studies/gear/3.4/lap.h5 " ] || fail "report so far: $grid"
# Gear 2.8 is the reference lap; the grid and motors have fewer than two points (the grid's two
# have the same pack) and are left out.
so_far=$(run_make report-so-far GEARS="2.8 3.0 3.4")
# The battery study has its two points and the reference lap at 51 MJ.
for heading in "Gear ratio (Fig. 12): 3 points" "Battery pack (Fig. 14): 3 points"; do
  grep -q "^## $heading" "$d/studies/report-so-far/report.md" || fail "report so far: $so_far"
done
for study in grid motors; do
  echo "$so_far" | grep -q "^$study: left out" || fail "report so far keeps $study: $so_far"
done

# An Ipopt solve not converged after ATTEMPT_ITERATIONS iterations (here 2, too few for any lap)
# is solved again from the nearest finished point of its study (gear 3.4) with NEIGHBOUR_FLAGS,
# again for ATTEMPT_ITERATIONS, then from the QSS guess with RETRY_FLAGS; the attempts set aside
# stay beside the lap.
run_make gear GEARS=3.2 ATTEMPT_ITERATIONS=2 LAP_FLAGS="$ipopt" 2> "$out/retry.log" > /dev/null ||
  fail "the retried gear 3.2: $(cat "$out/retry.log")"
for note in "not converged (exit 3); solving again with --init $d/studies/gear/3.4/lap.h5 --mu-strategy monotone --mu-init 1e-4 --max-iterations 2" \
    "not converged (exit 3); solving again from the QSS guess with --mu-globalization kkt-error"; do
  grep -q -- "$note" "$out/retry.log" || fail "gear 3.2 was not retried as expected: $(cat "$out/retry.log")"
done
/usr/bin/python3 - "$d/studies/gear/3.2" <<'PY'
import sys, h5py
point = sys.argv[1]
text = lambda v: v.decode() if isinstance(v, bytes) else str(v)
with h5py.File(f"{point}/lap-first-attempt.h5") as first, h5py.File(f"{point}/lap-second-attempt.h5") as second, \
        h5py.File(f"{point}/lap.h5") as lap:
    assert first.attrs["converged"] == 0 and first.attrs["max_iterations"] == 2, dict(first.attrs)
    assert text(first.attrs["mu_globalization"]) == "obj-constr-filter" and text(first.attrs["init_file"]) == ""
    assert second.attrs["converged"] == 0 and second.attrs["max_iterations"] == 2, dict(second.attrs)
    assert text(second.attrs["mu_strategy"]) == "monotone" and second.attrs["mu_init"] == 1e-4
    assert text(second.attrs["init_file"]).endswith("gear/3.4/lap.h5")
    assert lap.attrs["converged"] == 1 and text(lap.attrs["mu_globalization"]) == "kkt-error", dict(lap.attrs)
    assert text(lap.attrs["init_file"]) == "" and text(lap.attrs["mu_strategy"]) == "adaptive"
PY
# With no other point of its study solved, the second attempt is RETRY_FLAGS' and there is no
# third: make fails with the last attempt kept as lap-failed.h5.
! run_make "$d/studies/motors/3_4/lap.h5" ATTEMPT_ITERATIONS=2 LAP_FLAGS="$ipopt" 2> "$out/alone.log" > /dev/null ||
  fail "motors 3_4 converged in 2 iterations"
grep -q "solving again from the QSS guess with --mu-globalization kkt-error --max-iterations 2" "$out/alone.log" &&
  grep -q "no other point of the study has a lap to start from" "$out/alone.log" ||
  fail "motors 3_4 was not retried as expected: $(cat "$out/alone.log")"
p=$d/studies/motors/3_4
[ -s "$p/lap-failed.h5" ] && [ -s "$p/lap-first-attempt.h5" ] && [ ! -e "$p/lap.h5" ] ||
  fail "motors 3_4 left: $(ls "$p")"
# Under make -j2 a point waits for the point before it along the pack: 60 MJ starts from the copy
# of the gear study's 51 MJ point, which make would otherwise copy only after launching 60's solve.
run_make grid GRID_GEARS="4.0" GRID_MJ="60 51" WARM_START=yes LAP_FLAGS="$ipopt" -j2
init=$(/usr/bin/python3 -c 'import sys, h5py; v = h5py.File(sys.argv[1]).attrs["init_file"]; print(v.decode() if isinstance(v, bytes) else v)' "$d/studies/grid/4.0_60/lap.h5")
[ "$init" = "$d/studies/grid/4.0_51/lap.h5" ] || fail "grid 4.0_60 started from '$init', not from 4.0_51"
# An indirect solve that does not converge (here in one iteration: too few) is set aside and solved
# again by INDIRECT_RETRY_FLAGS (Ipopt with kkt-error) on the same mesh, without the indirect solver's
# --max-iterations (here in its FLAG=VALUE form): that converges, and the lap is Ipopt's.
p=$d/studies/gear/3.3
run_make "$p/lap.h5" LAP_FLAGS="--ds 20 --dt-max 0.5 --max-iterations=1" 2> "$out/indirect.log" > /dev/null ||
  fail "gear 3.3's retry by Ipopt: $(cat "$out/indirect.log")"
grep -q "$p: not converged (exit 3); solving again with --solver ipopt --mu-globalization kkt-error" "$out/indirect.log" ||
  fail "gear 3.3 was not retried by Ipopt: $(cat "$out/indirect.log")"
/usr/bin/python3 - "$p" <<'PY' || fail "gear 3.3's attempts: $(ls "$p")"
import sys, h5py
point = sys.argv[1]
text = lambda v: v.decode() if isinstance(v, bytes) else str(v)
with h5py.File(f"{point}/lap-first-attempt.h5") as first, h5py.File(f"{point}/lap.h5") as lap:
    assert first.attrs["converged"] == 0 and text(first.attrs["solver"]) == "indirect", dict(first.attrs)
    assert lap.attrs["converged"] == 1 and text(lap.attrs["solver"]) == "ipopt", dict(lap.attrs)
    assert lap.attrs["nodes"] == first.attrs["nodes"] and lap.attrs["mesh_dt_max"] == 0.5
    assert lap.attrs["max_iterations"] == 3000 and text(lap.attrs["mu_globalization"]) == "kkt-error", dict(lap.attrs)
PY
echo "pipeline on 3 km: ok"
