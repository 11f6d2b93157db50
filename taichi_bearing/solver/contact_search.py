"""The contact's search (Taichi functions and kernels of a
:class:`~taichi_bearing.solver.contact.PenaltyContact` ``c``): a uniform grid of square
cells over the surfaces' box, each segment binned in the cells its box grown by the
capture depth and a margin overlaps, and the list of queries within reach of a paired
segment (the only ones the step visits)."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import taichi as ti

__all__ = [
    "SCAN_BLOCK",
    "build_grid",
    "candidate",
    "cell_xy",
    "list_active",
    "member_cells",
    "scan_blocks",
    "seg_cells",
    "surface_motion",
]

# Running totals over many items (grid cells, queries) go by blocks: each block's total in
# parallel, a serial running total over the blocks, then each block's items in parallel,
# in order within the block. The same integers as one serial loop; but on a GPU a serial
# loop runs on one thread, and over every cell it took 1.4 ms a build on an H200.
SCAN_BLOCK = 256


def scan_blocks(n: int) -> int:
    """Blocks of :data:`SCAN_BLOCK` items that ``n`` items make (at least one)."""
    return max(1, -(-n // SCAN_BLOCK))


@ti.func
def block_range(b, n):
    """Items ``[lo, hi)`` of block ``b`` of ``n`` items."""
    return b * SCAN_BLOCK, ti.min((b + 1) * SCAN_BLOCK, n)


@ti.func
def exclusive_totals(blocks: ti.template(), nb):
    """Replace the first ``nb`` block totals by the sum of the blocks before each; return
    the sum of all."""
    run = 0
    for b in range(nb):
        t = blocks[b]
        blocks[b] = run
        run += t
    return run


@ti.func
def cell_xy(c: ti.template(), p):
    """Cell (column, row) of point ``p``, clamped to the grid."""
    cx = ti.min(ti.max(int(ti.floor((p[0] - c._ox) / c._h)), 0), c._nx - 1)
    cy = ti.min(ti.max(int(ti.floor((p[1] - c._oy) / c._h)), 0), c._ny - 1)
    return cx, cy


@ti.func
def member_cells(c: ti.template(), i):
    """First cell of the grid of node ``i``'s ensemble member: each member has a grid of
    its own (the members overlap in space; a shared grid would hold every member's
    segments in each cell)."""
    k = 0
    if ti.static(c._members > 1):
        k = i // c._member_nodes
    return k * c._nx * c._ny


@ti.func
def seg_cells(c: ti.template(), x: ti.template(), s):
    """Cell range covered by segment s's bounding box grown by ``grow``."""
    a, b = x[c.seg_a[s]], x[c.seg_b[s]]
    x0, y0 = cell_xy(c, ti.min(a, b) - c._grow)
    x1, y1 = cell_xy(c, ti.max(a, b) + c._grow)
    return x0, y0, x1, y1


@ti.kernel
def build_grid(c: ti.template(), x: ti.template()):
    """Bin every segment in the cells its box grown by capture depth + margin overlaps;
    remember the tracked nodes' positions (the reference of the next motion check)."""
    nx = c._nx
    n_cells = c._n_cells
    for cell in range(n_cells + 1):
        c.cell_start[cell] = 0
    for s in range(c.n_seg):
        x0, y0, x1, y1 = seg_cells(c, x, s)
        o = member_cells(c, c.seg_a[s])
        for cy in range(y0, y1 + 1):
            for cx in range(x0, x1 + 1):
                ti.atomic_add(c.cell_start[o + cy * nx + cx + 1], 1)
    # cell_start[cell + 1] holds the cell's count: a running total makes it the next
    # cell's start
    n_blocks = (n_cells + SCAN_BLOCK - 1) // SCAN_BLOCK
    for b in range(n_blocks):
        lo, hi = block_range(b, n_cells)
        total = 0
        for cell in range(lo, hi):
            total += c.cell_start[cell + 1]
        c.cell_block[b] = total
    ti.loop_config(serialize=True)
    for _ in range(1):
        exclusive_totals(c.cell_block, n_blocks)
    for b in range(n_blocks):
        lo, hi = block_range(b, n_cells)
        run = c.cell_block[b]
        for cell in range(lo, hi):
            run += c.cell_start[cell + 1]
            c.cell_start[cell + 1] = run
    for cell in range(n_cells):
        c.cell_fill[cell] = c.cell_start[cell]
    c.status[0] = 0
    for s in range(c.n_seg):
        x0, y0, x1, y1 = seg_cells(c, x, s)
        o = member_cells(c, c.seg_a[s])
        for cy in range(y0, y1 + 1):
            for cx in range(x0, x1 + 1):
                k = ti.atomic_add(c.cell_fill[o + cy * nx + cx], 1)
                if k < c.cap:
                    c.cell_items[k] = s
                    c.cell_surf[k] = c.seg_surf[s]
                else:
                    c.status[0] = 1
    for t in range(c.n_track):
        c.x_ref[t] = x[c.track[t]]


@ti.func
def candidate(c: ti.template(), S, i, k, xp, x: ti.template()):
    """Cell item k for query node i (at xp) of surface S: (segment, -1 when it is not
    of a paired surface or holds the node; xi, the node's projection on it, not
    clamped; squared true distance from the node to it)."""
    s = -1
    xi = 0.0
    d2 = 1e300
    if c.pass_pair[S * c.n_surf + c.cell_surf[k]] >= 0:
        sk = c.cell_items[k]
        ia, ib = c.seg_a[sk], c.seg_b[sk]
        if ia != i and ib != i:
            a = x[ia]
            d = x[ib] - a
            xi = (xp - a).dot(d) / d.dot(d)
            r = xp - (a + ti.min(ti.max(xi, 0.0), 1.0) * d)
            d2 = r.dot(r)
            s = sk
    return s, xi, d2


@ti.kernel
def list_active(c: ti.template(), x: ti.template()):
    """List, in query order, the queries within reach of a paired segment: true
    distance at most capture depth + margin + the query's patch reach (+ the largest
    arc sagitta), over the segments of its cell and the neighbouring ones.

    Until the next build a node and a segment's ends each move at most half the
    margin, so a query left out stays further than capture + patch reach from every
    segment: its own position is more than the capture depth behind any segment it
    projects onto, and its patch cannot reach one in front (either way no contact).
    It could only fall behind the line of a segment it does not project onto (beyond
    the segment's end), which is no contact either. So skipping it changes nothing,
    and most queries are skipped (a roller's surface is near a raceway only around
    its two contacts). A query left out while still holding a contact state is
    opened, as the contact loop would do at its next call."""
    nx, ny = c._nx, c._ny
    for q in range(c.n_query):
        S = c.q_surf[q]
        i = c.q_node[q]
        xp = x[i]
        hq = c.q_hmax[q]
        reach = c._activate_base + hq * (1.0 + 0.5 * c._kappa_max * hq)
        cx, cy = cell_xy(c, xp)
        o = member_cells(c, i)
        near = 0
        for oy in range(ti.max(cy - 1, 0), ti.min(cy + 2, ny)):
            for ox in range(ti.max(cx - 1, 0), ti.min(cx + 2, nx)):
                cell = o + oy * nx + ox
                for k in range(c.cell_start[cell], c.cell_start[cell + 1]):
                    s, _, d2 = candidate(c, S, i, k, xp, x)
                    if s >= 0 and d2 <= reach * reach:
                        near = 1
        c.q_near[q] = near
    # the list in query order (reproducible), by blocks of queries
    n_blocks = (c.n_query + SCAN_BLOCK - 1) // SCAN_BLOCK
    for b in range(n_blocks):
        lo, hi = block_range(b, c.n_query)
        count = 0
        for q in range(lo, hi):
            count += c.q_near[q]
        c.query_block[b] = count
    ti.loop_config(serialize=True)
    for _ in range(1):
        c.status[1] = exclusive_totals(c.query_block, n_blocks)
    for b in range(n_blocks):
        lo, hi = block_range(b, c.n_query)
        n = c.query_block[b]
        for q in range(lo, hi):
            if c.q_near[q] != 0:
                c.q_active[n] = q
                n += 1
            else:
                c._open(q)


@ti.kernel
def surface_motion(c: ti.template(), x: ti.template(), v: ti.template()):
    """The largest move of a tracked node since the last build, and the largest speed."""
    c.motion[0] = 0.0
    c.motion[1] = 0.0
    ti.loop_config(serialize=c._serial_light)
    for t in range(c.n_track):
        i = c.track[t]
        ti.atomic_max(c.motion[0], (x[i] - c.x_ref[t]).norm())
        ti.atomic_max(c.motion[1], v[i].norm())
