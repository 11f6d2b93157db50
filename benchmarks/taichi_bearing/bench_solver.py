"""Speed of the explicit solver: element-steps per second, Taichi vs a NumPy baseline.

Usage::

    python benchmarks/taichi_bearing/bench_solver.py [--sizes 10000 40000 160000] [--threads 1 2]
                                      [--arch cpu] [--json FILE] [--seconds 1.0]
                                      [--order mesh morton random]

Each Taichi thread count runs in its own subprocess (threads are fixed at ``ti.init``).
Compile time (first call) is reported apart and excluded from the rate. The NumPy
baseline is the same element (1-point St Venant-Kirchhoff quad with FB hourglass forces,
lumped-mass leapfrog) written with vectorised numpy in this file. The per-step overhead is
measured on a 2k-element mesh as time per step minus elements x the per-element time of
the 40k mesh. ``--order`` numbers the square mesh's nodes and elements as the mesher does
(row by row), along a Morton (Z-order) curve, or at random: how much the cost per element
owes to memory locality (each order its own row, ``taichi-cpu-morton`` etc.).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from taichi_bearing.case.material import Material  # noqa: E402
from taichi_bearing.mesh.primitives import rectangle_mesh  # noqa: E402
from taichi_bearing.solver.element import (  # noqa: E402
    element_geometry,
    hourglass_stiffness,
    materials_per_element,
)

STEEL = Material(210e9, 0.3, 7850.0)


def square_mesh(n_elements: int, order: str = "mesh"):
    """A square of about ``n_elements`` quads, numbered in ``order``."""
    n = max(2, round(np.sqrt(n_elements)))
    mesh = rectangle_mesh(0.1, 0.1, n, n)
    if order == "mesh":
        return mesh
    if order == "random":
        rng = np.random.default_rng(1)
        node_order = rng.permutation(mesh.n_nodes)
        element_order = rng.permutation(mesh.n_elements)
    else:
        node_order = np.argsort(morton_codes(mesh.nodes), kind="stable")
        centroids = mesh.nodes[mesh.elements].mean(axis=1)
        element_order = np.argsort(morton_codes(centroids), kind="stable")
    return renumbered(mesh, node_order, element_order)


def renumbered(mesh, node_order: np.ndarray, element_order: np.ndarray):
    """``mesh`` with node ``node_order[k]`` as node k and element ``element_order[k]`` as
    element k (connectivity, parts, node sets, surfaces and sensors follow)."""
    new = np.empty(mesh.n_nodes, dtype=np.int64)
    new[node_order] = np.arange(mesh.n_nodes)
    return replace(
        mesh,
        nodes=mesh.nodes[node_order],
        elements=new[mesh.elements[element_order]],
        element_part=mesh.element_part[element_order],
        node_sets={k: new[v] for k, v in mesh.node_sets.items()},
        surfaces={k: new[v] for k, v in mesh.surfaces.items()},
        sensor_nodes={k: int(new[v]) for k, v in mesh.sensor_nodes.items()},
    )


def morton_codes(points: np.ndarray, bits: int = 16) -> np.ndarray:
    """Z-order code of each point: its coordinates scaled to ``bits``-bit integers, their
    bits interleaved."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    q = ((points - lo) / np.maximum(hi - lo, 1e-300) * (2**bits - 1)).astype(np.uint64)
    code = np.zeros(len(points), dtype=np.uint64)
    for b in range(bits):
        for axis in range(2):
            bit = (q[:, axis] >> np.uint64(b)) & np.uint64(1)
            code |= bit << np.uint64(2 * b + axis)
    return code


def initial_velocity(n_nodes: int) -> np.ndarray:
    return np.random.default_rng(0).normal(scale=1e-3, size=(n_nodes, 2))


# ------------------------------------------------------------------ NumPy baseline


class NumpyModel:
    """The solver's element and leapfrog update in vectorised numpy (no constraints)."""

    def __init__(self, mesh, mat: Material, dt: float) -> None:
        self.conn = mesh.elements
        geo = element_geometry(mesh.nodes, mesh.elements)
        lam, mu, rho, ep = materials_per_element(mesh, mat)
        self.b, self.g, self.at = geo.b, geo.gamma, geo.area
        self.lam, self.mu = lam[:, None, None], mu[:, None, None]
        self.k = hourglass_stiffness(geo, ep, 1.0)
        mass = np.zeros(mesh.n_nodes)
        np.add.at(mass, mesh.elements, geo.shape_integrals * rho[:, None])
        self.minv = 1.0 / mass
        self.x = mesh.nodes.copy()
        self.v = initial_velocity(mesh.n_nodes)
        self.dt = dt
        self.flat = self.conn.ravel()
        self.n = mesh.n_nodes

    def step(self) -> None:
        xe = self.x[self.conn]  # (ne, 4, 2)
        F = np.einsum("eki,ekj->eij", xe, self.b)
        C = np.einsum("eki,ekj->eij", F, F)
        E = 0.5 * (C - np.eye(2))
        tr = (E[:, 0, 0] + E[:, 1, 1])[:, None, None]
        S = self.lam * tr * np.eye(2) + 2.0 * self.mu * E
        P = F @ S
        q = np.einsum("ek,eki->ei", self.g, xe)
        fe = -self.at[:, None, None] * np.einsum("eij,ekj->eki", P, self.b)
        fe -= (self.k[:, None] * q)[:, None, :] * self.g[:, :, None]
        f = np.stack(
            [
                np.bincount(self.flat, fe[..., 0].ravel(), self.n),
                np.bincount(self.flat, fe[..., 1].ravel(), self.n),
            ],
            axis=1,
        )
        self.v += self.dt * f * self.minv[:, None]
        self.x += self.dt * self.v


def bench_numpy(sizes: list[int], seconds: float) -> list[dict]:
    rows = []
    for ne_target in sizes:
        mesh = square_mesh(ne_target)
        model = NumpyModel(mesh, STEEL, 1e-8)
        model.step()
        n = 1
        while True:
            t0 = time.perf_counter()
            for _ in range(n):
                model.step()
            el = time.perf_counter() - t0
            if el > seconds or n > 100_000:
                break
            n *= 2
        rows.append(
            {
                "impl": "numpy",
                "threads": 1,
                "elements": mesh.n_elements,
                "element_steps_per_s": mesh.n_elements * n / el,
                "compile_s": 0.0,
                "us_per_step": el / n * 1e6,
            }
        )
    return rows


# ------------------------------------------------------------------ Taichi (subprocess)


def _time_steps(model, n: int, mode: str | None, repeats: int = 3) -> float:
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        model.advance(n, mode=mode)
        best = min(best, time.perf_counter() - t0)
    return best / n


def taichi_worker(
    arch: str, threads: int, sizes: list[int], seconds: float, orders: list[str]
) -> list[dict]:
    import tempfile

    from taichi_bearing.solver.backend import init_taichi
    from taichi_bearing.solver.model import Model

    # A fresh offline cache, so the reported compile time is a real compilation.
    init_taichi(arch, threads, cache_dir=tempfile.mkdtemp(prefix="bench_solver_cache_"))
    rows = []
    for ne_target, order in ((n, o) for n in sizes for o in orders):
        mesh = square_mesh(ne_target, order)
        model = Model(mesh, STEEL)
        model.set_state(v=initial_velocity(mesh.n_nodes))
        t0 = time.perf_counter()
        model.advance(1)
        first = time.perf_counter() - t0
        model.advance(5)
        t0 = time.perf_counter()
        model.advance(5)
        per = (time.perf_counter() - t0) / 5
        n = max(5, int(seconds / 3 / per))
        per_step = _time_steps(model, n, mode=None)  # as a run steps it
        rows.append(
            {
                "impl": f"taichi-{arch}" + ("" if order == "mesh" else f"-{order}"),
                "threads": threads,
                "elements": mesh.n_elements,
                "element_steps_per_s": mesh.n_elements / per_step,
                "compile_s": max(first - per_step, 0.0),
                "us_per_step": per_step * 1e6,
            }
        )
    # Per-step overhead on a 2k mesh: default stepping (serial kernel below 3000 elements)
    # and one launch per step; overhead = time per step - elements x per-element time.
    ref = next((r for r in rows if abs(r["elements"] - 40_000) < 2000), rows[0])
    per_element = 1.0 / ref["element_steps_per_s"]
    mesh = square_mesh(2000)
    model = Model(mesh, STEEL)
    model.set_state(v=initial_velocity(mesh.n_nodes))
    for mode, label in (("serial", "serial-block"), ("parallel", "launch-per-step")):
        model.advance(10, mode=mode)
        per_step = _time_steps(model, 2000 if mode == "serial" else 500, mode, repeats=5)
        rows.append(
            {
                "impl": f"taichi-{arch}-overhead-{label}",
                "threads": threads,
                "elements": mesh.n_elements,
                "element_steps_per_s": mesh.n_elements / per_step,
                "compile_s": 0.0,
                "us_per_step": per_step * 1e6,
                "overhead_us": (per_step - mesh.n_elements * per_element) * 1e6,
            }
        )
    return rows


def run_worker_subprocess(
    arch: str, threads: int, sizes: list[int], seconds: float, orders: list[str]
):
    cmd = [
        sys.executable,
        str(Path(__file__).resolve()),
        "--worker",
        "--arch",
        arch,
        "--threads",
        str(threads),
        "--seconds",
        str(seconds),
        "--sizes",
        *map(str, sizes),
        "--order",
        *orders,
    ]
    out = subprocess.run(cmd, capture_output=True, text=True, check=False, env=os.environ.copy())
    if out.returncode != 0:
        raise SystemExit(f"taichi worker ({arch}, {threads} threads) failed:\n{out.stderr[-2000:]}")
    line = [s for s in out.stdout.splitlines() if s.startswith("ROWS ")][-1]
    return json.loads(line[5:])


def print_table(rows: list[dict]) -> None:
    numpy_rate = {r["elements"]: r["element_steps_per_s"] for r in rows if r["impl"] == "numpy"}
    print(
        f"{'impl':34s} {'thr':>3s} {'elements':>8s} {'el-steps/s':>11s} {'us/step':>9s} "
        f"{'compile s':>9s} {'x numpy':>8s} {'overhead us':>11s}"
    )
    for r in rows:
        speedup = (
            r["element_steps_per_s"] / numpy_rate[r["elements"]]
            if (r["elements"] in numpy_rate and r["impl"] != "numpy")
            else float("nan")
        )
        over = r.get("overhead_us", float("nan"))
        print(
            f"{r['impl']:34s} {r['threads']:3d} {r['elements']:8d} "
            f"{r['element_steps_per_s']:11.3e} {r['us_per_step']:9.1f} {r['compile_s']:9.2f} "
            f"{speedup:8.1f} {over:11.1f}"
        )
    impls = sorted({r["impl"] for r in rows if "overhead" not in r["impl"]} - {"numpy"})
    for threads in sorted({r["threads"] for r in rows if r["impl"].startswith("taichi")}):
        for impl in impls:
            t = {
                r["elements"]: r["us_per_step"]
                for r in rows
                if r["threads"] == threads and r["impl"] == impl
            }
            big = sorted(t)
            if len(big) >= 2:
                print(
                    f"time ratio {big[-1]}/{big[-2]} elements, {impl}, {threads} thread(s): "
                    f"{t[big[-1]] / t[big[-2]]:.2f}"
                )


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", type=int, nargs="+", default=[10_000, 40_000, 160_000])
    p.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    p.add_argument("--arch", default="cpu", choices=["cpu", "cuda", "vulkan"])
    p.add_argument("--seconds", type=float, default=1.0, help="timed seconds per case")
    p.add_argument("--json", type=Path, default=None, help="also write the rows as JSON")
    p.add_argument(
        "--order", nargs="+", default=["mesh"], choices=["mesh", "morton", "random"],
        help="node and element numbering of the square meshes",
    )  # fmt: skip
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        rows = taichi_worker(args.arch, args.threads[0], args.sizes, args.seconds, args.order)
        print("ROWS " + json.dumps(rows))
        return 0
    rows = bench_numpy(args.sizes, args.seconds)
    for threads in args.threads:
        rows += run_worker_subprocess(args.arch, threads, args.sizes, args.seconds, args.order)
    print_table(rows)
    if args.json is not None:
        tmp = args.json.with_name(args.json.name + ".tmp")
        tmp.write_text(json.dumps(rows, indent=1))
        tmp.replace(args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
