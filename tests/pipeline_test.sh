#!/bin/sh
# The TT Zero pipeline (pipelines/Makefile) on the first 3 km of the Snaefell course, so that CI
# exercises it end to end: course -> road.h5 -> reference lap -> plots, then a two-point gear study
# whose second point is warm-started from the first, and the report of the studies so far.
# Usage: pipeline_test.sh BUILD_DIR SHARED_DATA
set -eu
build=$1 shared=$2
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
run_make() { make --no-print-directory -C "$here/../pipelines" BIN="$build" OUT="$out" SHARED="$shared" PIECE_M=3000 "$@"; }

run_make run
d=$out/snaefell-3000m
for f in road.h5 reference/lap.h5 reference/plots/summary.md reference/plots/speed.png reference/report.md; do
  [ -s "$d/$f" ] || fail "$d/$f missing"
done
grep -q "^converged      yes" "$d/reference/lap.txt" || fail "the reference lap did not converge: $(cat "$d/reference/lap.txt")"

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
# The battery study and the grid are solved from the largest pack down.
order=$(run_make -n battery grid PACK_MJ="30 60 42" GRID_GEARS="3.0 3.4" GRID_MJ="37 60" |
  grep -o "studies/[a-z]*/[0-9._]*/lap-attempt.h5 " | uniq | tr -d '\n')
[ "$order" = "studies/battery/60/lap-attempt.h5 studies/battery/42/lap-attempt.h5 studies/battery/30/lap-attempt.h5 \
studies/grid/3.0_60/lap-attempt.h5 studies/grid/3.4_60/lap-attempt.h5 studies/grid/3.0_37/lap-attempt.h5 \
studies/grid/3.4_37/lap-attempt.h5 " ] || fail "the order of the solves: $order"
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

run_make gear GEARS="3.0 3.4" WARM_START=yes -j1
for g in 3.0 3.4; do [ -s "$d/studies/gear/$g/lap.h5" ] || fail "gear $g: no lap.h5"; done
/usr/bin/python3 - "$d/studies/gear" <<'PY'
import sys, h5py
study = sys.argv[1]
with h5py.File(f"{study}/3.0/lap.h5") as a, h5py.File(f"{study}/3.4/lap.h5") as b:
    inits = [a.attrs["init_file"], b.attrs["init_file"]]
    inits = [i.decode() if isinstance(i, bytes) else str(i) for i in inits]
    # the first point cold-starts with Ipopt's default barrier, the second from the first with
    # NEIGHBOUR_FLAGS (a monotone barrier from 1e-4)
    assert inits[0] == "" and inits[1].endswith("gear/3.0/lap.h5"), inits
    text = lambda v: v.decode() if isinstance(v, bytes) else str(v)
    assert text(a.attrs["mu_strategy"]) == "adaptive", dict(a.attrs)
    assert text(b.attrs["mu_strategy"]) == "monotone" and b.attrs["mu_init"] == 1e-4, dict(b.attrs)
    assert "gear_ratio: 3.4" in (b.attrs["bike_yaml"].decode() if isinstance(b.attrs["bike_yaml"], bytes) else b.attrs["bike_yaml"])
    print("gear 3.0:", a.attrs["lap_time"], "s; gear 3.4:", b.attrs["lap_time"], "s")
PY
# The report so far: a point not copied yet stands in by the lap it will copy (grid 2.8_51 by the
# reference lap, 3.4_51 by gear 3.4); 2.8_37 and 3.4_37 are not solved.
grid=$(run_make -n report-so-far GRID_GEARS="2.8 3.4" GRID_MJ="37 51" | grep -o -- "--grid [^\\]*")
[ "$grid" = "--grid $d/reference/lap.h5 $d/studies/gear/3.4/lap.h5 " ] || fail "report so far: $grid"
# Gear 2.8 is the reference lap; the other studies have fewer than two points (the grid's two have
# the same pack) and are left out.
so_far=$(run_make report-so-far GEARS="2.8 3.0 3.4")
grep -q "^## Gear ratio (Fig. 12): 3 points" "$d/studies/report-so-far/report.md" || fail "report so far: $so_far"
for study in battery grid motors; do
  echo "$so_far" | grep -q "^$study: left out" || fail "report so far keeps $study: $so_far"
done

# An Ipopt solve not converged after ATTEMPT_ITERATIONS iterations (here 2, too few for any lap)
# is solved again from the nearest finished point of its study (gear 3.4) with NEIGHBOUR_FLAGS,
# again for ATTEMPT_ITERATIONS, then from the QSS guess with RETRY_FLAGS; the attempts set aside
# stay beside the lap.
run_make gear GEARS=3.2 ATTEMPT_ITERATIONS=2 2> "$out/retry.log" > /dev/null ||
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
! run_make battery PACK_MJ=45 ATTEMPT_ITERATIONS=2 2> "$out/alone.log" > /dev/null ||
  fail "battery 45 converged in 2 iterations"
grep -q "solving again from the QSS guess with --mu-globalization kkt-error --max-iterations 2" "$out/alone.log" &&
  grep -q "no other point of the study has a lap to start from" "$out/alone.log" ||
  fail "battery 45 was not retried as expected: $(cat "$out/alone.log")"
p=$d/studies/battery/45
[ -s "$p/lap-failed.h5" ] && [ -s "$p/lap-first-attempt.h5" ] && [ ! -e "$p/lap.h5" ] ||
  fail "battery 45 left: $(ls "$p")"
echo "pipeline on 3 km: ok"
