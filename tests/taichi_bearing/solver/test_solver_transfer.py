"""Copies between numpy and Taichi fields, many fields to one kernel (solver.transfer):
the same values and types as Taichi's own per-field copies, one compile per call."""

from __future__ import annotations

import numpy as np
import pytest
import taichi as ti

from taichi_bearing.solver import transfer
from taichi_bearing.solver.backend import init_taichi


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def _fields() -> list:
    """1-D fields of every supported kind, of different lengths."""
    return [
        ti.field(ti.f64, shape=7),
        ti.field(ti.i32, shape=3),
        ti.field(ti.i64, shape=5),
        ti.Vector.field(2, ti.f64, shape=11),
        ti.Vector.field(4, ti.i32, shape=2),
        ti.Vector.field(2, ti.i64, shape=6),
        ti.Vector.field(6, ti.f64, shape=1),
    ]


def _values(fields: list, seed: int) -> list[np.ndarray]:
    """Arrays for the fields: doubles with every bit used, integers near their limits."""
    rng = np.random.default_rng(seed)
    out = []
    for f in fields:
        shape = transfer.array_shape(f)
        if f.dtype == ti.f64:
            out.append(rng.standard_normal(shape) * 10.0 ** rng.integers(-300, 300, shape))
        else:
            info = np.iinfo(np.int32 if f.dtype == ti.i32 else np.int64)
            out.append(rng.integers(info.min, info.max, shape, dtype=info.dtype))
    return out


def _compiles(kernel) -> int:
    return len(kernel._primal.compiled_kernels)


def test_upload_and_download_give_taichis_own_values_and_types():
    fields = _fields()
    values = _values(fields, 1)
    transfer.upload(zip(fields, values, strict=True))
    for f, a in zip(fields, values, strict=True):
        own = f.to_numpy()  # Taichi's own copy of what upload wrote
        assert own.dtype == a.dtype and np.array_equal(own, a)
    again = _values(fields, 2)
    for f, a in zip(fields, again, strict=True):
        f.from_numpy(a)  # Taichi's own copy in, ours out
    for got, a in zip(transfer.download(fields), again, strict=True):
        assert got.dtype == a.dtype and got.shape == a.shape and np.array_equal(got, a)


def test_each_call_compiles_one_kernel_whatever_the_number_of_fields():
    fields = _fields()
    before = _compiles(transfer._k_copy)
    transfer.upload(zip(fields, _values(fields, 3), strict=True))
    assert _compiles(transfer._k_copy) == before + 1
    transfer.download(fields)
    assert _compiles(transfer._k_copy) == before + 2
    # the same fields again: nothing new to compile
    values = _values(fields, 4)
    transfer.upload(zip(fields, values, strict=True))
    assert all(np.array_equal(a, b) for a, b in zip(transfer.download(fields), values, strict=True))
    assert _compiles(transfer._k_copy) == before + 2


def test_more_fields_than_a_kernel_takes_are_copied_in_turns(recwarn):
    fields = [ti.field(ti.i32, shape=k + 1) for k in range(transfer.MAX_FIELDS + 9)]
    values = [np.arange(k + 1, dtype=np.int32) * 7 - k for k in range(len(fields))]
    transfer.upload(zip(fields, values, strict=True))
    got = transfer.download(fields)
    assert all(np.array_equal(a, b) for a, b in zip(got, values, strict=True))
    for k in (0, transfer.MAX_FIELDS - 1, transfer.MAX_FIELDS, len(fields) - 1):
        assert np.array_equal(fields[k].to_numpy(), values[k])  # Taichi's own read
    # Taichi warns when a static loop is unrolled more than 32 times
    assert not [w for w in recwarn if "unrolling" in str(w.message)]


def test_a_read_that_zeroes_returns_the_values_and_leaves_zeros():
    fields = _fields()
    values = _values(fields, 6)
    transfer.upload(zip(fields, values, strict=True))
    got = transfer.download(fields, zero=True)
    assert all(np.array_equal(a, b) for a, b in zip(got, values, strict=True))
    for f in fields:
        own = f.to_numpy()
        assert not own.any() and not np.signbit(own).any()  # +0, as fill(0) leaves


def test_fill_sets_every_component_of_every_field():
    fields = _fields()
    transfer.upload(zip(fields, _values(fields, 5), strict=True))
    transfer.fill(fields[:4], -3)
    for f in fields[:4]:
        assert np.all(f.to_numpy() == -3)
    transfer.fill(fields)
    assert all(not f.to_numpy().any() for f in fields)


def test_a_wrong_shape_or_an_unsupported_field_is_refused():
    f = ti.Vector.field(2, ti.f64, shape=4)
    g = ti.field(ti.f64, shape=2)
    transfer.upload([(g, np.ones(2))])
    with pytest.raises(ValueError, match=r"shape \(4, 3\) for a field of shape \(4, 2\)"):
        transfer.upload([(g, np.zeros(2)), (f, np.zeros((4, 3)))])
    assert np.all(g.to_numpy() == 1.0)  # nothing written when one array is wrong
    unsupported = [
        ti.field(ti.f64, shape=(2, 2)),
        ti.Matrix.field(2, 2, ti.f64, shape=3),
        ti.field(ti.f32, shape=3),
    ]
    for g in unsupported:
        assert not transfer.is_transferable(g)
        with pytest.raises(ValueError, match="transfer: "):
            transfer.download([g])
    assert transfer.is_transferable(f)
    assert transfer.upload([]) is None and transfer.download([]) == []
