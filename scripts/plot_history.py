#!/usr/bin/env python3
"""The history of a run (history.csv) as panels that fit the run, drawn by gnuplot into RESULTS/history.png.

The kind of run decides the panels (printed with the file name):
  quasi-static           load-displacement (each support's reaction against its prescribed displacement, a moving
                         obstacle's against its motion; the reactions against the prescribed force of a force-driven
                         run), energy (strain, and with friction the dissipation, against the work of the supports
                         and obstacles where it is known), contact forces, and with friction the ratio of tangential
                         to normal contact force against mu, else Newton iterations per step
  dynamic, free bodies   energies, their balance (E - E0 - W, with friction E + D - E0 - W, W the work of the loads
                         and moving obstacles; and the angular momentum without obstacles and loads, relative to the
                         run's energy and momentum scales), linear momentum, contact forces
  dynamic, supported     energies (with the work of the supports where known), load-displacement, contact forces,
                         Newton iterations
Contact panels appear only with contact; friction adds the dissipated energy and the stick/slip counts.
Usage: see `scripts/plot-history.sh --help`."""
import argparse
import csv
import math
import os
import subprocess
import sys
import tempfile

try:
    import yaml
except ImportError:  # python3-yaml (scripts/install-deps.sh); without it the scene's loads are not known
    yaml = None


def read_history(folder):
    path = os.path.join(folder, "history.csv")
    if not os.path.exists(path):
        raise SystemExit("plot-history: no %s (was the run made with --out?)" % path)
    with open(path) as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    if len(rows) < 2:
        raise SystemExit("plot-history: %s has no converged step to plot" % path)
    return rows


def read_scene(folder):
    """The effective scene the run wrote (scene.yaml), or {} when it cannot be read."""
    path = os.path.join(folder, "scene.yaml")
    if yaml is None or not os.path.exists(path):
        return {}
    try:
        with open(path) as f:
            scene = yaml.safe_load(f)
        return scene if isinstance(scene, dict) else {}
    except yaml.YAMLError:
        return {}


def scale_factor(history, t):
    """A boundary condition's `history` at time t: piecewise linear, constant outside (constant 1 when absent)."""
    if not history:
        return 1.0
    if t <= history[0][0]:
        return history[0][1]
    for (t0, f0), (t1, f1) in zip(history, history[1:]):
        if t <= t1:
            return f0 + (f1 - f0) * (t - t0) / (t1 - t0) if t1 > t0 else f1
    return history[-1][1]


def motion_at(motion, t):
    """An obstacle's translation at time t (piecewise linear through [t, dx, dy, dz])."""
    if not motion:
        return [0.0, 0.0, 0.0]
    points = [(m[0], [float(v) for v in m[1:4]]) for m in motion]
    if t <= points[0][0]:
        return points[0][1]
    for (t0, d0), (t1, d1) in zip(points, points[1:]):
        if t <= t1:
            s = (t - t0) / (t1 - t0) if t1 > t0 else 1.0
            return [a + s * (b - a) for a, b in zip(d0, d1)]
    return points[-1][1]


def number(value):
    try:
        return float(value)
    except (TypeError, ValueError):
        return None  # ~, null, free: a free component


class Run:
    """What the history and the scene say about the run."""

    def __init__(self, folder):
        self.rows = read_history(folder)
        self.scene = read_scene(folder)
        self.columns = set(self.rows[0])
        scheme = str(self.scene.get("time", {}).get("scheme", ""))
        kinetic = max(abs(r["kinetic_energy"]) for r in self.rows)
        self.dynamic = scheme not in ("", "quasi-static") if scheme else kinetic > 0.0
        self.contact = any(r["active_points"] > 0 for r in self.rows) or bool(self.scene.get("contact"))
        # Friction: points that stick or slip, or a dissipation above round-off of the run's energy (a frictionless
        # co-rotational contact reports its constraint's work, 1e-13 of the energy, as dissipated_energy).
        energy = max(max(abs(r["total_energy"]), abs(r["dissipated_energy"])) for r in self.rows)
        self.friction = any(r["stick_points"] + r["slip_points"] > 0 or abs(r["dissipated_energy"]) > 1e-9 * energy
                            for r in self.rows)
        self.drivers, self.force_driven, self.unknown_work = self.find_drivers()
        self.supported = bool(self.drivers) or self.force_driven or any(
            "displacement" in b for b in self.scene.get("boundary", []) or [])
        obstacles = [c for c in self.scene.get("contact", []) or [] if isinstance(c, dict) and "obstacle" in c]
        self.obstacles = bool(obstacles)
        self.body_force = any(abs(v) > 0 for v in self.scene.get("body_force", []) or [] if number(v) is not None)

    def find_drivers(self):
        """Curves (label, x per row, y column) of load-displacement: a support's prescribed displacement against its
        reaction, an obstacle's motion against the force it receives; force-driven: the applied load against every
        support's reaction. Also whether the work of the loads is unknown (tractions, resultants, body force)."""
        times = [r["time"] for r in self.rows]
        drivers, forces, supports = [], [], []
        self.support_columns = set()
        for k, bc in enumerate(self.scene.get("boundary", []) or []):
            if not isinstance(bc, dict):
                continue
            name = bc.get("name") or bc.get("group", "bc%d" % k)
            history = bc.get("history")
            for kind in ("displacement", "traction", "resultant"):
                for i, value in enumerate(bc.get(kind) or []):
                    v = number(value)
                    if v is None:
                        continue
                    column = "reaction_%s_%s" % (name, "xyz"[i])
                    if kind == "displacement":
                        if column in self.columns:
                            supports.append(column)
                            self.support_columns.add(column)
                        if v != 0.0 and column in self.columns:
                            drivers.append(("%s: u_%s" % (name, "xyz"[i]),
                                            [v * scale_factor(history, t) for t in times], column))
                    elif v != 0.0:
                        forces.append(("%s %s_%s" % (name, kind, "xyz"[i]),
                                       [v * scale_factor(history, t) for t in times]))
        for k, pair in enumerate(self.scene.get("contact", []) or []):
            obstacle = pair.get("obstacle") if isinstance(pair, dict) else None
            if not isinstance(obstacle, dict) or not obstacle.get("motion"):
                continue
            name = obstacle.get("name") or obstacle.get("type", "obstacle")
            track = [motion_at(obstacle["motion"], t) for t in times]
            for i in range(3):
                column = "reaction_%s_%s" % (name, "xyz"[i])
                if column in self.columns and any(abs(d[i]) > 0 for d in track):
                    drivers.append(("%s: d_%s" % (name, "xyz"[i]), [d[i] for d in track], column))
        force_driven = bool(forces)
        self.load_is_force = force_driven and not drivers
        if self.load_is_force:  # the supports' reactions against the applied load
            label, load = forces[0]
            largest = max((abs(r[column]) for column in supports for r in self.rows), default=0.0)
            drivers = [("%s against %s" % (column, label), load, column) for column in supports
                       if max(abs(r[column]) for r in self.rows) > 1e-9 * largest]
        self.loads = force_driven or self.body_force_in(self.scene)
        # history.csv's external_work holds the loads' work (tractions, resultants, body force); older files do not
        return drivers, force_driven, self.loads and "external_work" not in self.columns

    @staticmethod
    def body_force_in(scene):
        return any(number(v) not in (None, 0.0) for v in scene.get("body_force", []) or [])

    def external_work(self):
        """The work on the bodies per row: the loads' (history.csv's external_work) plus the supports' and moving
        obstacles' (trapezoidal in time), or None when it is not known (a history.csv without external_work)."""
        if self.unknown_work or not self.scene:
            return None
        work, total = [self.rows[0].get("external_work", 0.0)], 0.0
        for a, b in zip(self.rows, self.rows[1:]):
            for label, x, column in self.drivers:
                i = self.rows.index(b)
                dx = x[i] - x[i - 1]
                force = 0.5 * (a[column] + b[column])
                total += force * dx if column in self.support_columns else -force * dx  # an obstacle receives it
            work.append(total + b.get("external_work", 0.0))
        return work


DERIVED = ["E_change", "EplusD_change", "Lx_change", "Ly_change", "Lz_change", "work", "strain_plus_dissipated",
           "E_plus_D", "friction_ratio"]


def write_data(run, path):
    """history.csv's columns and the derived series (DERIVED, then driver<k>_x, driver<k>_y), one row per step."""
    rows = run.rows
    e0 = rows[0]["total_energy"]
    e_scale = max(abs(e0), max(abs(r["total_energy"]) for r in rows), 1e-300)
    l_norm = [math.sqrt(sum(r["angular_momentum_" + k] ** 2 for k in "xyz")) for r in rows]
    l_scale = max(max(l_norm), 1e-300)
    work = run.external_work()
    vertical = "z" if any(abs(q["contact_force_z"]) > 0 for q in rows) else "y"
    run.friction_ratio = []
    names = list(rows[0]) + DERIVED + [n for k in range(len(run.drivers)) for n in ("driver%d_x" % k, "driver%d_y" % k)]
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        for i, r in enumerate(rows):
            e, d = r["total_energy"], r["dissipated_energy"]
            normal = abs(r["contact_force_" + vertical])
            tangential = math.sqrt(max(sum(r["contact_force_" + k] ** 2 for k in "xyz") - normal * normal, 0.0))
            run.friction_ratio.append(tangential / normal if normal > 0 else float("nan"))
            w = work[i] if work else 0.0
            values = list(r.values()) + [(e - e0 - w) / e_scale, (e + d - e0 - w) / e_scale] + \
                [(r["angular_momentum_" + k] - rows[0]["angular_momentum_" + k]) / l_scale for k in "xyz"] + \
                [work[i] if work else float("nan"), r["strain_energy"] + r["kinetic_energy"] + d, e + d,
                 run.friction_ratio[-1]]
            for label, x, column in run.drivers:
                values += [x[i], r[column]]
            f.write(",".join("%.10g" % v for v in values) + "\n")
    return e_scale, l_scale


def choose_panels(run):
    if run.dynamic and not run.supported:
        panels = ["energy", "conservation", "momentum"]
    elif run.dynamic:
        panels = ["energy", "load"] if run.drivers else ["energy", "momentum"]
    else:
        panels = ["load"] if run.drivers else ["reactions"]
        panels.append("energy")
    if run.contact:
        panels.append("contact")
        if not run.dynamic and run.friction:
            panels.append("friction")
    if len(panels) < 4:
        panels.append("newton")
    return panels[:4] if len(panels) <= 4 else panels


PANEL_NAMES = {"energy": "energy", "conservation": "conservation", "momentum": "linear momentum",
               "load": "load-displacement", "reactions": "reactions", "contact": "contact forces",
               "friction": "friction ratio", "newton": "Newton iterations"}


def gnuplot_panel(panel, run, data, e_scale, l_scale):
    """gnuplot commands of one panel; `data` is write_data's file."""
    def curve(column, title, style="with lines lw 2", x="time", axes="", every=""):
        return '"%s" %susing "%s":"%s" %s%s title "%s"' % (data, every, x, column, axes, style, title)
    friction, lines = run.friction, []
    plot = lambda curves: lines.append("plot " + ", \\\n     ".join(curves))  # noqa: E731
    if panel == "energy":
        work = run.external_work() is not None and (run.drivers or run.loads)
        if run.dynamic:
            title = "energy" + (" and dissipation" if friction else "")
            curves = [curve("kinetic_energy", "kinetic"), curve("strain_energy", "strain"),
                      curve("total_energy", "total E")]
        else:
            title = "energy: strain" + (" + dissipated" if friction else "") + \
                (" against the work of the supports" if work else "")
            curves = [curve("strain_energy", "strain")]
        if friction:
            curves += [curve("dissipated_energy", "dissipated D"),
                       curve("E_plus_D" if run.dynamic else "strain_plus_dissipated",
                             "E + D" if run.dynamic else "strain + D", 'with lines lw 2 dt 2 lc rgb "black"')]
        if work:
            doers = (["loads"] if run.loads else []) + (["supports and obstacles"] if run.drivers else [])
            curves.append(curve("work", "work of the " + " and ".join(doers), 'with lines lw 2 dt 3 lc rgb "#a00000"'))
        lines.append('set title "%s"' % title)
        plot(curves)
    elif panel == "conservation":
        # W: the loads' and moving obstacles' work; unknown (an older history.csv with loads): E - E0 alone
        w = " - W" if run.external_work() is not None and (run.loads or run.drivers) else ""
        torque_free = not run.obstacles and not run.loads
        lines.append('set title "%s: (E%s - E0%s) / %.3g%s"' % (
            "balance" if w else "conservation", " + D" if friction else "", w, e_scale,
            ", (L - L0) / %.3g" % l_scale if torque_free else ""))
        lines.append('set format y "%.1e"')
        curves = [curve("EplusD_change" if friction else "E_change",
                        "(E + D - E0%s)/scale" % w if friction else "(E - E0%s)/scale" % w)]
        if torque_free:
            curves += [curve("L%s_change" % k, "(L%s - L%s0)/|L|" % (k, k)) for k in "xyz"]
        plot(curves)
        lines.append('set format y "%g"')
    elif panel == "momentum":
        lines.append('set title "linear momentum"')
        plot([curve("momentum_%s" % k, "p%s" % k) for k in "xyz"])
    elif panel == "load":
        force_only = run.load_is_force
        lines.append('set title "load-displacement: reaction against the prescribed %s"' %
                     ("load" if force_only else "displacement"))
        lines.append('set xlabel "prescribed %s"\nset ylabel "force on the body"' %
                     ("load" if force_only else "displacement"))
        plot([curve("driver%d_y" % k, label.replace("_", " "), "with linespoints lw 2 pt 7 ps 0.4",
                    x="driver%d_x" % k) for k, (label, _, _) in enumerate(run.drivers)])
        lines.append('set xlabel "time"\nunset ylabel')
    elif panel == "reactions":
        lines.append('set title "support reactions"')
        reaction = sorted(col for col in run.columns if col.startswith("reaction_") and
                          any(abs(r[col]) > 0 for r in run.rows))
        plot([curve(col, col.replace("_", " ")) for col in reaction] or [curve("strain_energy", "no reactions")])
    elif panel == "contact":
        lines.append('set title "contact force on the slave side, %s points"' % ("stick/slip" if friction else
                                                                                 "active"))
        lines.append("set y2tics\nset ytics nomirror")
        largest = {k: max(abs(r["contact_force_" + k]) for r in run.rows) for k in "xyz"}
        curves = [curve("contact_force_%s" % k, "F%s" % k) for k in "xyz"  # components above round-off
                  if largest[k] > 1e-9 * max(largest.values())] or [curve("contact_force_x", "F")]
        counts = ["stick_points", "slip_points"] if friction else ["active_points"]
        most = max(max(r[col] for r in run.rows) for col in counts)
        lines.append("set y2range [0:%g]" % max(1.0, 1.15 * most))  # the largest count below the frame
        colours = {"stick_points": "#606060", "active_points": "#606060", "slip_points": "#d62728"}
        curves += [curve(col, "%s (right)" % col.replace("_points", ""), 'with steps lw 1 lc rgb "%s"' % colours[col],
                         axes="axes x1y2 ") for col in counts]
        plot(curves)
        lines.append("unset y2tics\nset ytics mirror\nset autoscale y2")
    elif panel == "friction":
        lines.append('set title "friction: tangential / normal contact force"')
        mu = friction_coefficient(run.scene)
        curves = [curve("friction_ratio", "|F_t| / F_n")]
        if mu:
            curves.append("%g with lines dt 2 lc rgb 'black' title 'mu = %g'" % (mu, mu))
        top = max([mu or 0.0] + [v for v in run.friction_ratio if v == v])  # the line of mu below the frame
        lines.append("set yrange [0:%g]" % (1.15 * top) if top > 0 else "set yrange [0:*]")
        plot(curves)
        lines.append("set autoscale y")
    elif panel == "newton":
        lines.append('set title "Newton iterations per step, step size"')
        largest = max(r["newton_iterations"] for r in run.rows)
        lines.append("set y2tics\nset ytics nomirror\nset yrange [0:%g]\nset y2range [0:%g]" %
                     (max(1.0, 1.15 * largest), 1.15 * max(r["dt"] for r in run.rows)))
        lines.append("set boxwidth 0.7 relative\nset style fill solid 0.4")
        lines.append("set xrange [%.10g:%.10g]" % (run.rows[0]["time"], run.rows[-1]["time"]))
        plot([curve("newton_iterations", "Newton iterations", "with boxes", every="every ::1 "),  # row 0: no step
              curve("dt", "dt (right)", "with steps lw 2", axes="axes x1y2 ", every="every ::1 ")])
        lines.append("set autoscale x")
        lines.append("set autoscale y\nset autoscale y2\nunset y2tics\nset ytics mirror\nset style fill empty")
    return "\n".join(lines) + "\n"


def friction_coefficient(scene):
    for pair in scene.get("contact", []) or []:
        mu = number((pair.get("parameters") or {}).get("mu")) if isinstance(pair, dict) else None
        if mu:
            return mu
    return None


def main():
    parser = argparse.ArgumentParser(prog="plot-history.sh", description="\n".join(__doc__.split("\n")[:-1]),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results", help="a results folder written by `stickslip run --out`")
    parser.add_argument("title", nargs="?", help="title of the picture (default: the folder name)")
    parser.add_argument("--size", type=lambda s: [int(v) for v in s.split("x")],
                        help="pixels, WxH (default 1400x900 for four panels, 1400x520 for three in a row)")
    args = parser.parse_args()
    folder = args.results
    run = Run(folder)
    panels = choose_panels(run)
    title = args.title or os.path.basename(os.path.normpath(folder))
    kind = ("dynamic" if run.dynamic else "quasi-static") + (", friction" if run.friction else "") + \
           (", contact" if run.contact and not run.friction else "")
    png = os.path.join(folder, "history.png")
    with tempfile.TemporaryDirectory(prefix="stickslip-history-") as tmp:
        data = os.path.join(tmp, "history.csv")
        e_scale, l_scale = write_data(run, data)
        rows = 1 if len(panels) <= 3 else 2
        columns = (len(panels) + rows - 1) // rows
        size = args.size or ([1400, 900] if rows == 2 else [1400, 520])
        script = ['set datafile separator ","',
                  'set terminal pngcairo size %d,%d noenhanced font ",10"' % tuple(size),
                  'set output "%s"' % png.replace('"', '\\"'), "set key below horizontal", "set grid",
                  "set offsets 0, 0, graph 0.05, graph 0.05",
                  'set multiplot layout %d,%d title "%s (%s)"' % (rows, columns, title.replace('"', "'"), kind),
                  'set xlabel "time"']
        for panel in panels:
            script.append(gnuplot_panel(panel, run, data, e_scale, l_scale))
        script.append("unset multiplot")
        proc = subprocess.run(["gnuplot"], input="\n".join(script) + "\n", text=True, capture_output=True)
        if proc.returncode != 0:
            raise SystemExit("plot-history: gnuplot failed:\n" + proc.stderr)
    # the picture is the run's: the next run into the folder replaces it with the rest
    subprocess.run([os.path.join(os.path.dirname(os.path.abspath(__file__)), "claim-results-files.sh"), folder,
                    "history.png"], check=True)
    print("plot-history: %s (%s): %s" % (png, kind, ", ".join(PANEL_NAMES[p] for p in panels)))


if __name__ == "__main__":
    main()
