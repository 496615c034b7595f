"""Runs KarstNSim (PyPI pykarstnsim, its C++ core) on a karstgen scene, for the side-by-side
benchmark of `cargo xtask bench --peer` (issue 21).

Reads the scene TOML that karstgen reads (fixtures/bench/karstnsim-peer.toml): the domain, the
plane terrain, the plane water tables, the sinks, the springs and the connectivity matrix, and
hands them to pykarstnsim with every optional constraint off (no inception surface, fracture,
karstification potential, noise, amplification or section simulation), the same k and a Poisson
radius given on the command line (KarstNSim's radius is a fraction of the domain's smallest
extent; the bench picks it so that both programs sample the same count within 2 %).

Prints one line `peer samples N segments M` on stdout; the caller times the whole process.

Usage: python pykarstnsim_run.py SCENE.toml --poisson-radius F --k K --out DIR
"""

import argparse
import contextlib
import io
import math
import pathlib
import re
import sys
import tomllib

import pykarstnsim_core as core

from pykarstnsim.config import KarstConfig
from pykarstnsim.karstnsim import run_simulation
from pykarstnsim.models import ConnectivityMatrix, ProjectBox, Sink, Spring, Surface

# Grid of the project box (KarstNSim's density and potential properties live on it; both are
# uniform here).
BOX_CELLS = (20, 16, 12)


def plane_surface(z, domain, margin=1.0):
    """A two-triangle surface over the domain's footprint (1 m wider on every side), its
    vertices at height z(x, y)."""
    (x0, y0, _), (x1, y1, _) = domain
    corners = [(x, y) for y in (y0 - margin, y1 + margin) for x in (x0 - margin, x1 + margin)]
    points = [core.Vector3(x, y, z(x, y)) for x, y in corners]
    return Surface(core.Surface(points, [core.Triangle(0, 1, 2), core.Triangle(1, 3, 2)]))


def terrain_z(terrain):
    if terrain.get("kind") != "plane":
        sys.exit(f"peer run: terrain kind {terrain.get('kind')!r}: only plane terrains are handed to KarstNSim")
    (ox, oy), (gx, gy) = terrain.get("origin", [0.0, 0.0]), terrain.get("gradient", [0.0, 0.0])
    return lambda x, y: terrain["elevation"] + gx * (x - ox) + gy * (y - oy)


def water_table_z(table):
    """karstgen's plane surface: through (origin, elevation), dipping `dip` degrees towards the
    azimuth `dip_direction` (degrees clockwise from north)."""
    ox, oy = table.get("origin", [0.0, 0.0])
    slope = math.tan(math.radians(table.get("dip", 0.0)))
    azimuth = math.radians(table.get("dip_direction", 0.0))
    dx, dy = math.sin(azimuth), math.cos(azimuth)
    return lambda x, y: table["elevation"] - slope * ((x - ox) * dx + (y - oy) * dy)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("scene", type=pathlib.Path)
    parser.add_argument("--poisson-radius", type=float, required=True)
    parser.add_argument("--k", type=int, required=True)
    parser.add_argument("--out", type=pathlib.Path, required=True)
    args = parser.parse_args()

    scene = tomllib.loads(args.scene.read_text())
    lo, hi = scene["domain"]["min"], scene["domain"]["max"]
    tables = scene["geology"]["water_tables"]
    table_index = {t["name"]: i for i, t in enumerate(tables)}
    keypoints = scene["keypoints"]
    sinks = [k for k in keypoints if k["kind"] == "sink"]
    springs = [k for k in keypoints if k["kind"] == "spring"]

    config = KarstConfig(
        karstic_network_name="peer",
        save_directory=args.out,
        selected_seed=scene.get("seed", 1),
        use_density_property=False,
        poisson_radius=args.poisson_radius,
        nghb_count=args.k,
        fraction_karst_perm=0.7,
        add_inception_surfaces=False,
        use_karstification_potential=False,
        karstification_potential_weight=0.0,
        use_fracture_constraints=False,
        nb_deadend_points=0,
        refine_surface_sampling=0,
    )
    box = ProjectBox(
        basis=tuple(lo),
        u=(hi[0] - lo[0], 0.0, 0.0),
        v=(0.0, hi[1] - lo[1], 0.0),
        w=(0.0, 0.0, hi[2] - lo[2]),
        cells_u=BOX_CELLS[0],
        cells_v=BOX_CELLS[1],
        cells_w=BOX_CELLS[2],
    )
    footprint = (lo, hi)
    args.out.mkdir(parents=True, exist_ok=True)
    log = io.StringIO()
    with contextlib.redirect_stdout(log):
        result = run_simulation(
            config=config,
            project_box=box,
            # KarstNSim's sink and spring indices are 1-based rows and columns of the matrix.
            sinks=[Sink(tuple(s["position"]), index=i + 1, order=1) for i, s in enumerate(sinks)],
            springs=[
                Spring(tuple(s["position"]), index=i + 1, water_table_index=table_index[s["water_table"]])
                for i, s in enumerate(springs)
            ],
            connectivity_matrix=ConnectivityMatrix(scene["connectivity"]["matrix"]),
            water_tables=[plane_surface(water_table_z(t), footprint) for t in tables],
            topo_surface=plane_surface(terrain_z(scene["terrain"]), footprint),
        )
    (args.out / "karstnsim.log").write_text(log.getvalue())
    if result is None:
        sys.exit(f"peer run: KarstNSim returned no network (log: {args.out / 'karstnsim.log'})")
    print(f"peer samples {sample_count(log.getvalue())} segments {len(result.segments)}")


def sample_count(log):
    """The size of KarstNSim's sampling cloud, from the lines of its log that say how many points
    it sampled and added."""
    counts = re.findall(r"^\* (?:Using|Added) (\d+) (?:automatically sampled )?points", log, re.M)
    removed = re.findall(r"^\* Removed (\d+) points", log, re.M)
    if not counts:
        sys.exit("peer run: KarstNSim's log names no sample count")
    return sum(map(int, counts)) - sum(map(int, removed))


if __name__ == "__main__":
    main()
