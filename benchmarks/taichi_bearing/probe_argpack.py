"""Kernels over fields against kernels over an argument pack of ndarrays: what a new model
costs in compiling, and what a step costs, on a toy spring chain (a proposal's evidence, not
the solver).

The solver's kernels take the model as ``ti.template()``: Taichi compiles them again for
every new ``Model`` (its fields are new), 4-6 s a model on this VM, most of the test suite's
time. A ``ti.types.argpack`` of ndarrays is a kernel argument of a fixed type: the kernel
compiles once per process. This script builds three models each way, times each one's first
call (compile included), then times calls of both, alternating which goes first, and checks
that both give the same bits. Usage::

    python benchmarks/taichi_bearing/probe_argpack.py [--nodes 400000] [--calls 30] [--rounds 4]
"""

import argparse
import time

import numpy as np
import taichi as ti

vec2 = ti.math.vec2


def pack_type():
    return ti.types.argpack(
        x=ti.types.ndarray(dtype=vec2, ndim=1),
        v=ti.types.ndarray(dtype=vec2, ndim=1),
        f=ti.types.ndarray(dtype=vec2, ndim=1),
        links=ti.types.ndarray(dtype=ti.i32, ndim=2),
        n=ti.i32,
        dt=ti.f64,
    )


@ti.func
def chain_step(m: ti.template(), dt):
    """One step of a chain of unit springs, on fields or on a pack: the same code."""
    for e in range(m.n):
        a, b = m.links[e, 0], m.links[e, 1]
        d = m.x[b] - m.x[a]
        s = d.norm() - 1.0
        m.f[a] += s * d
        m.f[b] -= s * d
    for i in range(m.n):
        m.v[i] += dt * m.f[i]
        m.x[i] += dt * m.v[i]
        m.f[i] = vec2(0.0)


@ti.data_oriented
class FieldModel:
    def __init__(self, x0: np.ndarray, links: np.ndarray) -> None:
        n = len(x0)
        self.x, self.v, self.f = (ti.Vector.field(2, ti.f64, n) for _ in range(3))
        self.links = ti.field(ti.i32, (n, 2))
        self.x.from_numpy(x0)
        self.links.from_numpy(links)
        self.n = n

    @ti.kernel
    def step(self, dt: ti.f64):
        chain_step(self, dt)

    def positions(self) -> np.ndarray:
        return self.x.to_numpy()


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--nodes", type=int, default=400_000)
    p.add_argument("--calls", type=int, default=30)
    p.add_argument("--rounds", type=int, default=4)
    args = p.parse_args()
    ti.init(arch=ti.cpu, default_fp=ti.f64, offline_cache=False, cpu_max_num_threads=1)
    if ti.lang.impl.current_cfg().arch != ti.cpu:
        raise SystemExit("Taichi did not start on the CPU")
    Pack = pack_type()

    @ti.kernel
    def pack_step(m: Pack):
        chain_step(m, m.dt)

    def pack_model(x0: np.ndarray, links: np.ndarray):
        n = len(x0)
        x, v, f = (ti.ndarray(vec2, n) for _ in range(3))
        x.from_numpy(x0)
        ln = ti.ndarray(ti.i32, (n, 2))
        ln.from_numpy(links)
        return Pack(x=x, v=v, f=f, links=ln, n=n, dt=1e-6), x

    rng = np.random.default_rng(0)
    print("first call of each new model (compile included), ms")
    print("| model | nodes | fields | argument pack |\n|---:|---:|---:|---:|")
    for k in range(3):
        n = 1000 + k
        x0 = rng.random((n, 2))
        links = np.stack([np.arange(n), (np.arange(n) + 1) % n], 1).astype(np.int32)
        fm = FieldModel(x0, links)
        t = time.perf_counter()
        fm.step(1e-6)
        ti.sync()
        t_field = time.perf_counter() - t
        pm, _ = pack_model(x0, links)
        t = time.perf_counter()
        pack_step(pm)
        ti.sync()
        t_pack = time.perf_counter() - t
        print(f"| {k + 1} | {n} | {t_field * 1e3:.1f} | {t_pack * 1e3:.1f} |")

    n = args.nodes
    x0 = rng.random((n, 2))
    links = np.stack([np.arange(n), (np.arange(n) + 1) % n], 1).astype(np.int32)
    fm = FieldModel(x0, links)
    pm, px = pack_model(x0, links)
    runs = {"fields": lambda: fm.step(1e-6), "argument pack": lambda: pack_step(pm)}
    for run in runs.values():  # compiled before any timing
        run()
    ti.sync()
    times: dict[str, list[float]] = {name: [] for name in runs}
    for r in range(args.rounds):
        order = list(runs) if r % 2 == 0 else list(runs)[::-1]
        for name in order:
            t = time.perf_counter()
            for _ in range(args.calls):
                runs[name]()
            ti.sync()
            times[name].append((time.perf_counter() - t) / args.calls * 1e3)
    print(f"\na call on {n} nodes, ms (best of {args.rounds} rounds of {args.calls}, alternating)")
    print("| kernel over | best | all rounds |\n|---|---:|---|")
    for name, ts in times.items():
        print(f"| {name} | {min(ts):.2f} | {', '.join(f'{t:.2f}' for t in ts)} |")
    ratio = min(times["argument pack"]) / min(times["fields"])
    same = np.array_equal(px.to_numpy(), fm.positions())
    print(f"\nargument pack / fields: {ratio:.3f}; positions identical after "
          f"{1 + args.rounds * args.calls} steps: {same}")  # fmt: skip


if __name__ == "__main__":
    main()
