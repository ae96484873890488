#!/usr/bin/python3
"""Plots of an optimal lap (lap.h5, docs/lap_h5.md) and, with --road, of its road (road.h5,
docs/road_h5.md), plus summary.md.

usage: lap_plots.py lap.h5 [--road road.h5] -o OUTDIR

Writes into OUTDIR (created if missing), each file atomically:
  speed.png          V and the quasi-steady-state qss/V [km/h] vs distance [km]
  battery.png        pack terminal voltage [V], current [A], power drawn [kW] (paper Fig. 8)
  motor.png          motor voltage [V], current [A], electric power [kW] (paper Fig. 9)
  power.png          power to the ground wheel/power vs power drawn battery/power [kW] (Fig. 11)
  yaw_roll.png       roll angle phi [deg] and yaw rate Omega_z [deg/s]
  resim.png          (when the lap has resim/*) each state's re-simulation difference, scaled
                     [1, log], with the check's 0.1 %: where the mesh does not resolve the dynamics
  sensitivity.png    (when the lap has sensitivity/*: the indirect solver's) what buys lap time:
                     the SENSITIVITY_BARS largest sensitivities of design values (sensitivity/kind:
                     not the rider's limits, the conditions or the motor's reference temperature),
                     the lap time 1 % more of each bike value costs [s] (negative: buys), largest
                     at the top
  map.png            (--road) the bike's path coloured by speed [km/h] on the road's local
                     east/north frame [km]; path = centre line + n across the (banked) road surface
  elevation.png      (--road) centre-line elevation z [m], slope tan(sigma) [%] and, on a banked
                     road, banking [deg] (road.h5 version 2; version 1 is level) vs distance
  summary.md         lap time (m:ss.s), energy used (MJ, % of the pack), top speed
road.h5 always holds planar x/y (docs/road_h5.md: local transverse Mercator metres), so the map
uses them, not lat/lon. The road must be the lap's: its length within 1 m of the lap's
`road_length`. All input is read and checked before anything is written.
"""
import math
import os

import numpy as np

import ttz_h5

LAP_CHANNELS = ("state/V", "qss/V", "state/n", "state/phi",
                "battery/voltage", "battery/current", "battery/power",
                "motor/voltage", "motor/current", "motor/power", "wheel/power")
# The states of resim/<state> in two panels: the path, speed and power train, whose differences
# stay small, and the tyre, roll and heave modes, which the mesh resolves least (docs/lap.md
# "Re-simulation").
RESIM_PANELS = (("path and power train", ("n", "alpha", "V", "T", "e", "Omega_z", "tau_w")),
                ("tyre, roll and heave", ("beta", "z", "phi", "omega_w", "omega_phi", "z_dot")))
RESIM_TOLERANCE = 1e-3  # the check's 0.1 % (lap/resimulate.h)
RESIM_FLOOR = 1e-12     # plotted in place of 0 (the first node) on the log axis
SENSITIVITY_BARS = 15
ROAD_CHANNELS = ("s", "x", "y", "z", "theta", "sigma", "banking")
ROAD_LENGTH_TOLERANCE_M = 1.0
KMH = 3.6  # (km/h) per (m/s)


def read_lap(path):
    """The lap's channels by dataset name (units of docs/lap_h5.md), 's' [m], 'Omega_z' [rad/s],
    'qss/s' [m], and its summary attributes."""
    lap = ttz_h5.open_lap(path)
    s = lap.data("s")
    channels = {name: lap.data(name, s.size) for name in LAP_CHANNELS}
    channels.update(s=s, Omega_z=ttz_h5.omega_z(lap, s.size), **{"qss/s": lap.data("qss/s")})
    resim = [f"resim/{name}" for _, names in RESIM_PANELS for name in names]
    if all(lap.has(name) for name in resim):  # added within version 3 (docs/lap_h5.md)
        channels.update({name: lap.data(name, s.size) for name in resim})
    channels["sensitivities"] = ttz_h5.sensitivities(lap)
    attrs = {name: lap.attr(name) for name in
             ("lap_time", "energy_used", "energy_fraction", "top_speed", "road_length")}
    attrs.update(converged=lap.attr("converged", int), message=lap.attr("message", str))
    return channels, attrs


def read_road(path, lap_road_length, names=ROAD_CHANNELS):
    """The road's datasets `names` (of its centre line: m, rad, 1/m) by name, checked to be the
    lap's road."""
    road = ttz_h5.open_road(path)
    s = road.data("s")
    channels = {name: ttz_h5.road_banking(road, s.size) if name == "banking" else road.data(name, s.size)
                for name in names}
    length = road.attr("length_m")
    if abs(length - lap_road_length) > ROAD_LENGTH_TOLERANCE_M:
        raise ttz_h5.InputError(path, f"road length {length:.1f} m is not the lap's road_length "
                                f"{lap_road_length:.1f} m: a lap of another road")
    return channels


def format_lap_time(seconds):
    """m:ss.s of a time in seconds (minutes not wrapped into hours)."""
    minutes = int(seconds // 60)
    return f"{minutes}:{seconds - 60 * minutes:04.1f}"


def summary_text(lap_name, attrs):
    """summary.md: lap time, energy [MJ, % of pack], top speed [m/s, km/h]."""
    pack = attrs["energy_used"] / attrs["energy_fraction"] if attrs["energy_fraction"] else math.nan
    lines = [f"# Lap summary: {lap_name}", "",
             f"- lap time: {format_lap_time(attrs['lap_time'])} ({attrs['lap_time']:.1f} s)",
             f"- energy used: {attrs['energy_used'] / 1e6:.2f} MJ "
             f"({100 * attrs['energy_fraction']:.1f} % of the {pack / 1e6:.2f} MJ pack)",
             f"- top speed: {attrs['top_speed']:.1f} m/s ({KMH * attrs['top_speed']:.1f} km/h)",
             f"- converged: {'yes' if attrs['converged'] else 'no: ' + attrs['message']}", ""]
    return "\n".join(lines)


def distance_axis(axis):
    """Labels the x axis as distance along the centre line [km]."""
    axis.set_xlabel("distance s [km]")
    axis.grid(True, alpha=0.3)


def stacked_figure(plt, s, panels, title):
    """One panel per (label, values, unit scale) sharing the distance axis s [m]."""
    figure, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(10, 2.4 * len(panels)))
    for axis, (label, values, scale) in zip(np.atleast_1d(axes), panels):
        axis.plot(s / 1e3, values * scale, lw=0.8)
        axis.set_ylabel(label)
        axis.grid(True, alpha=0.3)
    distance_axis(np.atleast_1d(axes)[-1])
    figure.suptitle(title)
    figure.tight_layout()
    return figure


def speed_figure(plt, lap):
    """V and qss/V [km/h] vs s [km]."""
    figure, axis = plt.subplots(figsize=(10, 4))
    axis.plot(lap["s"] / 1e3, KMH * lap["state/V"], lw=0.9, label="optimal lap V")
    axis.plot(lap["qss/s"] / 1e3, KMH * lap["qss/V"], lw=0.8, ls="--", label="quasi-steady qss/V")
    axis.set_ylabel("speed [km/h]")
    axis.legend()
    distance_axis(axis)
    figure.tight_layout()
    return figure


def electric_figure(plt, lap, group, title):
    """Voltage [V], current [A], power [kW] of `group` ('battery' or 'motor') vs s."""
    panels = [(f"{group} voltage [V]", lap[f"{group}/voltage"], 1.0),
              (f"{group} current [A]", lap[f"{group}/current"], 1.0),
              (f"{group} power [kW]", lap[f"{group}/power"], 1e-3)]
    return stacked_figure(plt, lap["s"], panels, title)


def power_figure(plt, lap):
    """Power to the ground (wheel/power) and drawn from the pack (battery/power) [kW] vs s."""
    figure, axis = plt.subplots(figsize=(10, 4))
    axis.plot(lap["s"] / 1e3, 1e-3 * lap["battery/power"], lw=0.8, label="drawn from the pack")
    axis.plot(lap["s"] / 1e3, 1e-3 * lap["wheel/power"], lw=0.8, label="to the ground (wheel)")
    axis.set_ylabel("power [kW]")
    axis.legend()
    distance_axis(axis)
    figure.tight_layout()
    return figure


def yaw_roll_figure(plt, lap):
    """Roll angle [deg] and yaw rate [deg/s] vs s (right positive, the model's frame)."""
    panels = [("roll phi [deg]", lap["state/phi"], 180 / math.pi),
              ("yaw rate Omega_z [deg/s]", lap["Omega_z"], 180 / math.pi)]
    return stacked_figure(plt, lap["s"], panels, "roll and yaw (right positive)")


def resim_figure(plt, lap):
    """Each state's scaled re-simulation difference resim/<state> [1] vs s, log scale, with the
    check's tolerance."""
    figure, axes = plt.subplots(len(RESIM_PANELS), 1, sharex=True, figsize=(10, 3.2 * len(RESIM_PANELS)))
    for axis, (title, names) in zip(axes, RESIM_PANELS):
        for name in names:
            axis.semilogy(lap["s"] / 1e3, np.maximum(lap[f"resim/{name}"], RESIM_FLOOR), lw=0.6, label=name)
        axis.axhline(RESIM_TOLERANCE, color="k", ls="--", lw=0.8, label="0.1 % (the check)")
        axis.set_ylabel("difference / scale")
        axis.set_title(title)
        axis.legend(fontsize=7, ncol=4)
        axis.grid(True, alpha=0.3)
    distance_axis(axes[-1])
    figure.suptitle("re-simulation: each state integrated from the window's start against the lap")
    figure.tight_layout()
    return figure


def sensitivity_figure(plt, lap):
    """The largest sensitivities of design values (sensitivity/kind) as horizontal bars [s per 1 %
    more], largest at the top: red where more of the value costs time, green where it buys time."""
    largest, _ = ttz_h5.largest_sensitivities(lap["sensitivities"], SENSITIVITY_BARS)
    keys = [row[0] for row in largest][::-1]
    seconds = np.array([row[2] for row in largest][::-1])
    figure, axis = plt.subplots(figsize=(9, 0.35 * len(keys) + 1.5))
    axis.barh(keys, seconds, color=np.where(seconds > 0, "tab:red", "tab:green"))
    axis.axvline(0.0, color="k", lw=0.8)
    axis.set_xlabel("lap time per 1 % more of the value [s]")
    axis.tick_params(axis="y", labelsize=7)
    axis.grid(True, axis="x", alpha=0.3)
    axis.set_title("what buys lap time: design values (by the adjoint, lap/sensitivity.h)")
    figure.tight_layout()
    return figure


def bike_path(lap, road):
    """East/north [m] of the bike: the centre line interpolated at the lap's s, moved by n
    (right positive) across the road surface: minus the east/north part of the road's left
    vector, (-cos xi sin theta - sin xi sin sigma cos theta, cos xi cos theta - sin xi sin sigma
    sin theta) (docs/road_h5.md), which is the horizontal normal on a road without banking."""
    x, y, theta, sigma, xi = (np.interp(lap["s"], road["s"], road[k]) for k in ("x", "y", "theta", "sigma", "banking"))
    n = lap["state/n"]
    left_x = -np.cos(xi) * np.sin(theta) - np.sin(xi) * np.sin(sigma) * np.cos(theta)
    left_y = np.cos(xi) * np.cos(theta) - np.sin(xi) * np.sin(sigma) * np.sin(theta)
    return x - n * left_x, y - n * left_y


def map_figure(plt, lap, road):
    """The bike's path coloured by speed [km/h] on the road's local frame [km]."""
    from matplotlib.collections import LineCollection

    x, y = bike_path(lap, road)
    points = np.column_stack([x, y]) / 1e3
    segments = np.stack([points[:-1], points[1:]], axis=1)
    speed = KMH * 0.5 * (lap["state/V"][:-1] + lap["state/V"][1:])
    figure, axis = plt.subplots(figsize=(8, 8))
    lines = LineCollection(segments, cmap="viridis", linewidths=2)
    lines.set_array(speed)
    axis.add_collection(lines)
    axis.plot(road["x"] / 1e3, road["y"] / 1e3, color="0.8", lw=0.5, zorder=0)
    axis.plot(*points[0], "ko")
    axis.set_aspect("equal")
    axis.autoscale()
    axis.set_xlabel("east [km]")
    axis.set_ylabel("north [km]")
    figure.colorbar(lines, ax=axis, label="speed [km/h]", shrink=0.7)
    figure.tight_layout()
    return figure


def road_panels(road):
    """(label, values, scale) of elevation z [m], slope tan(sigma) [%] and, on a banked road,
    banking [deg], and the figure's title."""
    panels = [("elevation z [m]", road["z"], 1.0),
              ("slope [%]", np.tan(road["sigma"]), 100.0)]
    if np.any(road["banking"] != 0.0):
        panels.append(("banking [deg]", np.degrees(road["banking"]), 1.0))
        return panels, "road: elevation, slope (uphill positive) and banking (left border higher positive)"
    return panels, "road: elevation and slope (uphill positive)"


def elevation_figure(plt, road):
    """The road's panels (road_panels) vs s."""
    panels, title = road_panels(road)
    return stacked_figure(plt, road["s"], panels, title)


def figures(plt, lap, road):
    """{file name: figure builder} of every PNG to write."""
    builders = {
        "speed.png": lambda: speed_figure(plt, lap),
        "battery.png": lambda: electric_figure(plt, lap, "battery", "battery (paper Fig. 8)"),
        "motor.png": lambda: electric_figure(plt, lap, "motor", "motor (paper Fig. 9)"),
        "power.png": lambda: power_figure(plt, lap),
        "yaw_roll.png": lambda: yaw_roll_figure(plt, lap),
    }
    if "resim/n" in lap:
        builders["resim.png"] = lambda: resim_figure(plt, lap)
    if ttz_h5.largest_sensitivities(lap["sensitivities"], 1)[0]:
        builders["sensitivity.png"] = lambda: sensitivity_figure(plt, lap)
    if road is not None:
        builders["map.png"] = lambda: map_figure(plt, lap, road)
        builders["elevation.png"] = lambda: elevation_figure(plt, road)
    return builders


def parse_args():
    """Command line."""
    parser = ttz_h5.argument_parser(__doc__)
    parser.add_argument("lap", help="lap.h5")
    parser.add_argument("--road", help="road.h5 of the lap (map, elevation, slope and banking plots)")
    parser.add_argument("-o", "--outdir", required=True, help="output folder")
    return parser.parse_args()


def main():
    """Reads everything, then writes the PNGs and summary.md."""
    args = parse_args()
    lap, attrs = read_lap(args.lap)
    road = read_road(args.road, attrs["road_length"]) if args.road else None
    os.makedirs(args.outdir, exist_ok=True)
    builders = figures(ttz_h5.pyplot(), lap, road)
    for name, build in builders.items():
        ttz_h5.save_figure(build(), os.path.join(args.outdir, name))
    ttz_h5.write_text(os.path.join(args.outdir, "summary.md"),
                      summary_text(os.path.basename(args.lap), attrs))
    print(f"wrote {len(builders)} PNGs and summary.md to {args.outdir}")


if __name__ == "__main__":
    ttz_h5.run_cli(main)
