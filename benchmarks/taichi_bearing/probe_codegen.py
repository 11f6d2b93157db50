"""What machine code Taichi makes of the element forces on this CPU: vector width, fused
multiply-adds, and the instruction mix of one element.

Compiles a serial loop of :func:`~taichi_bearing.solver.element_forces.element_forces` (a
small square mesh, stiffness-proportional damping on) with Taichi's assembly printout
(``print_kernel_asm``, into a temporary folder), and prints the CPU's model and family,
which SIMD registers the loop uses (``xmm`` 128-bit, ``ymm`` 256, ``zmm`` 512), whether it
has fused multiply-adds, and the counts of its floating-point instructions. The element
loop's cost is set by these: a loop of ~300 instructions per element at two doubles a
vector runs at about the speed the profile shows (``profile_step.py``), and a compiler that
used this CPU's wider vectors or FMA would run it faster. (The printout comes from
Taichi's own compile; the code it runs was read once with gdb on the 2-core VM for a small
loop: the same 128-bit operations, VEX-encoded, and no FMA.) Where the CPU has AVX2 and
the loop uses neither wider registers nor FMA, it says that Taichi's optimiser took the CPU
for baseline x86-64 (its LLVM cannot name it). Takes a few seconds.

    python benchmarks/taichi_bearing/probe_codegen.py
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import collections
import os
import platform
import re
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


def _cpuinfo() -> str | None:
    try:
        return Path("/proc/cpuinfo").read_text()
    except OSError:
        return None


def simd_flags() -> list[str]:
    """Which of avx2, fma and avx512f the CPU reports (Linux; none known elsewhere)."""
    flags = re.search(r"^flags\s*:\s*(.*)$", _cpuinfo() or "", re.MULTILINE)
    return [f for f in ("avx2", "fma", "avx512f") if flags and f in flags.group(1).split()]


def cpu_name() -> str:
    """The CPU's model name, family and model (Linux), else the platform's word."""
    text = _cpuinfo()
    if text is None:
        return platform.processor() or platform.machine()
    field = {k: re.search(rf"^{k}\s*:\s*(.*)$", text, re.MULTILINE) for k in
             ("model name", "cpu family", "model")}  # fmt: skip
    value = {k: m.group(1).strip() if m else "?" for k, m in field.items()}
    simd = simd_flags()
    return (f"{value['model name']} (family {value['cpu family']}, model {value['model']}; "
            f"has {', '.join(simd) or 'none of avx2, fma, avx512f'})")  # fmt: skip


def main() -> int:
    import taichi as ti

    out = Path(tempfile.mkdtemp(prefix="probe_codegen_"))
    os.chdir(out)  # Taichi writes its printouts into the working folder
    from taichi_bearing.solver.backend import init_taichi

    start = ti.init

    def init_printing(**kwargs):
        # The project's start (arch checked, f64), with the printout on and no cache (a
        # cached kernel is not compiled, so not printed).
        return start(**{**kwargs, "print_kernel_asm": True, "offline_cache": False})

    ti.init = init_printing
    try:
        init_taichi("cpu", 1)
    finally:
        ti.init = start
    from benchmarks.taichi_bearing.bench_solver import STEEL, square_mesh
    from taichi_bearing.solver import Model
    from taichi_bearing.solver.damping import StiffnessDamping
    from taichi_bearing.solver.element_forces import element_forces

    model = Model(square_mesh(400), STEEL, damping=StiffnessDamping(0.02, 2.0e4))

    @ti.kernel
    def probe_element_loop(m: ti.template(), dt: ti.f64):
        ti.loop_config(serialize=True)
        for e in range(m.n_elements):
            element_forces(m, e, dt, 1)

    probe_element_loop(model, 1.0e-8)
    text = next(
        (p.read_text() for p in sorted(out.glob("*.s")) if "probe_element_loop" in p.read_text()),
        "",
    )
    if not text:
        print(f"no assembly printout found in {out}")
        return 1
    body = text[text.index("probe_element_loop") :]
    ops = collections.Counter(re.findall(r"^\s+([a-z][a-z0-9]*)", body, re.MULTILINE))
    regs = {r: len(re.findall(rf"%{r}\d+", body)) for r in ("xmm", "ymm", "zmm")}
    fp = {
        k: n
        for k, n in ops.items()
        if re.fullmatch(r"v?(mul|add|sub|div|fmadd\w*|fnmadd\w*|fmsub\w*)[sp][sd]", k)
    }  # noqa: E501
    fma = sum(n for k, n in ops.items() if "fmadd" in k or "fmsub" in k or "fnm" in k)
    print(f"CPU: {cpu_name()}")
    print(f"Taichi {'.'.join(map(str, ti.__version__))}: element loop, {sum(ops.values())} "
          "instructions (one damped element; Taichi's own printout)")  # fmt: skip
    print(f"  registers used: xmm (128-bit) {regs['xmm']}, ymm (256) {regs['ymm']}, "
          f"zmm (512) {regs['zmm']}")  # fmt: skip
    print(f"  fused multiply-adds: {fma}")
    print(f"  floating-point arithmetic: {dict(sorted(fp.items(), key=lambda kv: -kv[1]))}")
    if "avx2" in simd_flags() and regs["ymm"] == regs["zmm"] == 0 and fma == 0:
        # Taichi 1.7 builds its optimiser's target from LLVM's name for the host CPU and
        # no feature list: a CPU its LLVM cannot name is taken for baseline x86-64.
        print("  the optimiser took this CPU for baseline x86-64 (SSE2): Taichi's LLVM does not"
              " name it (docs/results/speed/: on this VM that costs one thread ~1.1x)")  # fmt: skip
    print(f"  printout: {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
