"""A model's energy sums read back in a fixed order (:meth:`Model.energies
<taichi_bearing.solver.model.Model.energies>`): a kernel of its own, module-level so that
any model (a template) can be measured."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import taichi as ti

__all__ = ["MEASURE_BLOCK", "measure_energies"]

MEASURE_BLOCK = 256  # items a thread sums in the energy read-out (Model.energies)


@ti.kernel
def measure_energies(model: ti.template()):
    """Each member's kinetic energy, external work and sum m |u|^2 over its nodes, strain,
    hourglass and damping energies over its elements, into ``model.sums[6 k ...]``."""
    # Blocks of MEASURE_BLOCK items, each summed by one thread, then the blocks by one
    # thread per member (the compiled order is fixed, though fast math may regroup a
    # loop's additions): the same sums on any thread count, and a member's the same as
    # its model's alone, without one thread's dependent chain over every node and
    # element (on a GPU that chain took ~18 ms an output sample, more than the sample's
    # 186 steps).
    nb = model.n_node_blocks
    per = model.n_sum_blocks
    for j in range(model.ensemble_size * per):
        k = j // per
        b = j - k * per
        s = ti.Vector([0.0, 0.0, 0.0], dt=ti.f64)
        if b < nb:
            n0 = k * model.member_nodes
            i1 = ti.min((b + 1) * MEASURE_BLOCK, model.member_nodes)
            for i in range(n0 + b * MEASURE_BLOCK, n0 + i1):
                m = model.mass[i]
                u = model.x[i] - model.X[i]
                s += ti.Vector([0.5 * m * model.v_int[i].dot(model.v_int[i]), model.work[i],
                                m * u.dot(u)])  # fmt: skip
        else:
            e0 = k * model.member_elements
            lo = (b - nb) * MEASURE_BLOCK
            for e in range(e0 + lo, e0 + ti.min(lo + MEASURE_BLOCK, model.member_elements)):
                s += ti.Vector([model.e_int[e], model.e_hg[e], model.e_damp[e]])
        model.sum_parts[j] = s
    for k in range(model.ensemble_size):
        nodes = ti.Vector([0.0, 0.0, 0.0], dt=ti.f64)
        elements = ti.Vector([0.0, 0.0, 0.0], dt=ti.f64)
        for b in range(per):
            if b < nb:
                nodes += model.sum_parts[k * per + b]
            else:
                elements += model.sum_parts[k * per + b]
        o = 6 * k
        model.sums[o], model.sums[o + 4], model.sums[o + 5] = nodes[0], nodes[1], nodes[2]
        model.sums[o + 1], model.sums[o + 2], model.sums[o + 3] = (
            elements[0], elements[1], elements[2],
        )  # fmt: skip
