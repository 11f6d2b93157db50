"""A model's energy sums read back in a fixed order (:meth:`Model.energies
<taichi_bearing.solver.model.Model.energies>`): a kernel of its own, module-level so that
any model (a template) can be measured."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import taichi as ti

__all__ = ["MEASURE_BLOCK", "measure_energies"]

MEASURE_BLOCK = 256  # items a thread sums in the energy read-out (Model.energies)


@ti.kernel
def measure_energies(model: ti.template()):
    """Kinetic energy, external work and sum m |u|^2 over the nodes, strain, hourglass and
    damping energies over the elements, into ``model.sums``."""
    # Blocks of MEASURE_BLOCK items, each summed by one thread, then the blocks by one
    # thread (the compiled order is fixed, though fast math may regroup a loop's
    # additions): the same sums on any thread count, without
    # one thread's dependent chain over every node and element (on a GPU that chain
    # took ~18 ms an output sample, more than the sample's 186 steps).
    nb = model.n_node_blocks
    for b in range(model.sum_parts.shape[0]):
        s = ti.Vector([0.0, 0.0, 0.0], dt=ti.f64)
        if b < nb:
            for i in range(b * MEASURE_BLOCK, ti.min((b + 1) * MEASURE_BLOCK, model.n_nodes)):
                m = model.mass[i]
                u = model.x[i] - model.X[i]
                s += ti.Vector([0.5 * m * model.v_int[i].dot(model.v_int[i]), model.work[i],
                                m * u.dot(u)])  # fmt: skip
        else:
            e0 = (b - nb) * MEASURE_BLOCK
            for e in range(e0, ti.min(e0 + MEASURE_BLOCK, model.n_elements)):
                s += ti.Vector([model.e_int[e], model.e_hg[e], model.e_damp[e]])
        model.sum_parts[b] = s
    for _ in range(1):
        nodes = ti.Vector([0.0, 0.0, 0.0], dt=ti.f64)
        elements = ti.Vector([0.0, 0.0, 0.0], dt=ti.f64)
        for b in range(model.sum_parts.shape[0]):
            if b < nb:
                nodes += model.sum_parts[b]
            else:
                elements += model.sum_parts[b]
        model.sums[0], model.sums[4], model.sums[5] = nodes[0], nodes[1], nodes[2]
        model.sums[1], model.sums[2], model.sums[3] = elements[0], elements[1], elements[2]
