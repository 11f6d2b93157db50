"""Time histories of a run (sensors, roller contact forces, energies), written as they come.

A Parquet file cannot be read until its footer is written, so a run never appends to one
file. Rows are buffered and every ``chunk_rows`` rows the buffer is written as its own small
Parquet file ``<stem>.parts/part-000001.parquet`` (temporary name, then rename). A crash,
even ``kill -9``, therefore loses at most the rows still in the buffer. ``close()`` (also
run by the context manager on an exception or Ctrl-C) merges the parts into
``histories.parquet`` (and ``histories.csv`` on request), again write-then-rename, and then
removes the parts.

What is on disk at any moment reads back as: the merged file, followed by the parts' rows
later than its last time. :func:`read_histories` applies exactly that rule, so it reads a
finished run, a crashed one and a crashed resumed one alike.

File and column names are those of :mod:`taichi_bearing.output.run_folder` (re-exported here for
the writers): ``time_s``; ``<sensor>_ux|uy|vx|vy|ax|ay``; ``roller<j>_<race>_fx|fy|fn|ft``;
``energy_<kind>``.
"""

from __future__ import annotations

import os
import shutil
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from bearing_io.files import atomic_path
from taichi_bearing.output.layout import (
    ENERGY_KINDS,
    HISTORIES_FILE,
    RACES,
    ROLLER_FORCE_COMPONENTS,
    SENSOR_QUANTITIES,
    TIME_COLUMN,
    energy_columns,
    history_columns,
    roller_force_columns,
    sensor_columns,
)

__all__ = [
    "ENERGY_KINDS",
    "RACES",
    "SENSOR_QUANTITIES",
    "ROLLER_FORCE_COMPONENTS",
    "TIME_COLUMN",
    "HistoryWriter",
    "energy_columns",
    "history_columns",
    "read_histories",
    "roller_force_columns",
    "sensor_columns",
]

_MERGED_NAME = HISTORIES_FILE
_PART_GLOB = "part-*.parquet"


# --------------------------------------------------------------------------- paths


def _resolve(folder_or_path: str | os.PathLike) -> Path:
    """The merged file's path: ``folder/histories.parquet`` or the ``.parquet`` path given."""
    p = Path(folder_or_path)
    return p if p.suffix == ".parquet" else p / _MERGED_NAME


def _parts_dir(merged: Path) -> Path:
    return merged.with_name(merged.stem + ".parts")


def _part_files(parts_dir: Path) -> list[Path]:
    # Temporary files start with "." and do not match the glob; numbers are zero-padded,
    # so a name sort is a write-order sort.
    return sorted(parts_dir.glob(_PART_GLOB)) if parts_dir.is_dir() else []


def _read_on_disk(merged: Path) -> pa.Table | None:
    """The rows on disk: the merged file, then the parts' rows later than its last time."""
    tables = []
    last = -np.inf
    if merged.is_file():
        t = pq.read_table(merged)
        tables.append(t)
        if t.num_rows:
            last = t.column(TIME_COLUMN)[-1].as_py()
    parts = _part_files(_parts_dir(merged))
    if parts:
        p = pa.concat_tables([pq.read_table(f) for f in parts])
        if tables and p.column_names != tables[0].column_names:
            raise ValueError(f"{_parts_dir(merged)}: part columns differ from those of {merged}")
        times = p.column(TIME_COLUMN).to_numpy()
        tables.append(p.filter(pa.array(times > last)))
    if not tables:
        return None
    return pa.concat_tables(tables) if len(tables) > 1 else tables[0]


def read_histories(path: str | os.PathLike) -> pd.DataFrame:
    """Read the histories of a run, finished or not.

    Parameters
    ----------
    path : str or path-like
        The run folder, or the ``histories.parquet`` path (which need not exist when only
        the chunk parts of a crashed run are on disk).

    Returns
    -------
    pandas.DataFrame
        One row per record, ``time_s`` first.

    Raises
    ------
    FileNotFoundError
        If neither the merged file nor any part exists.
    """
    merged = _resolve(path)
    table = _read_on_disk(merged)
    if table is None:
        raise FileNotFoundError(
            f"no histories at {merged} (nor chunk parts in {_parts_dir(merged)})"
        )
    return table.to_pandas()


# --------------------------------------------------------------------------- writer


class HistoryWriter:
    """Append rows of a run's histories; flush them to disk in chunks.

    Parameters
    ----------
    folder_or_path : str or path-like
        Run folder (the file is ``histories.parquet`` in it) or the ``.parquet`` path.
    columns : sequence of str
        Column names, the first ``"time_s"``; see :func:`history_columns`.
    chunk_rows : int
        Rows per chunk file. A crash loses at most this many rows.
    csv : bool
        Also write ``histories.csv`` beside the Parquet file on close.
    resume_time : float, optional
        Continue an earlier run: its rows (merged file and/or parts) are kept up to and
        including this time (the checkpoint time), later ones are dropped, and appending
        continues after them. The columns must be the same. Without it, a previous run's
        histories at this path are removed.
    max_wall_s : float
        Also flush when the oldest buffered row is older than this many seconds of wall
        time, so a slow run does not keep a long stretch only in memory.

    Notes
    -----
    Times must increase strictly from row to row (checked). Call :meth:`flush` before
    saving a checkpoint so that the histories on disk reach the checkpoint time.

    Examples
    --------
    Three rows into the run folder ``run`` (``run/histories.parquet``), read back:

    >>> with HistoryWriter("run", ["time_s", "top_ay"]) as hist:
    ...     for k in range(3):
    ...         hist.append([k * 1e-5, 0.5 * k])
    >>> read_histories("run")["top_ay"].tolist()
    [0.0, 0.5, 1.0]
    """

    def __init__(
        self,
        folder_or_path: str | os.PathLike,
        columns: Sequence[str],
        chunk_rows: int = 4096,
        csv: bool = False,
        resume_time: float | None = None,
        max_wall_s: float = 60.0,
    ) -> None:
        columns = [str(c) for c in columns]
        if not columns or columns[0] != TIME_COLUMN:
            raise ValueError(f"the first history column must be {TIME_COLUMN!r}, got {columns[:1]}")
        dup = sorted({c for c in columns if columns.count(c) > 1})
        if dup:
            raise ValueError(f"duplicate history columns: {dup}")
        if int(chunk_rows) != chunk_rows or chunk_rows < 1:
            raise ValueError(f"chunk_rows must be a positive integer, got {chunk_rows!r}")
        self.path = _resolve(folder_or_path)
        self.csv_path = self.path.with_suffix(".csv") if csv else None
        self.columns = columns
        self.chunk_rows = int(chunk_rows)
        self.max_wall_s = float(max_wall_s)
        self._parts = _parts_dir(self.path)
        self._schema = pa.schema([(c, pa.float64()) for c in columns])
        self._buffer = np.empty((self.chunk_rows, len(columns)), dtype=np.float64)
        self._n_buffered = 0
        self._next_part = 1
        self._last_time = -np.inf
        self._buffer_since = 0.0
        self._closed = False
        self.path.parent.mkdir(parents=True, exist_ok=True)
        if resume_time is None:
            self._start_fresh()
        else:
            self._resume(float(resume_time))

    # -- opening

    def _start_fresh(self) -> None:
        shutil.rmtree(self._parts, ignore_errors=True)
        self.path.unlink(missing_ok=True)
        if self.csv_path is not None:
            self.csv_path.unlink(missing_ok=True)

    def _resume(self, resume_time: float) -> None:
        table = _read_on_disk(self.path)
        if table is None:
            kept = self._schema.empty_table()
        else:
            if table.column_names != self.columns:
                raise ValueError(
                    f"cannot resume {self.path}: its columns differ from this run's "
                    f"({len(table.column_names)} on disk, {len(self.columns)} now)"
                )
            times = table.column(TIME_COLUMN).to_numpy()
            kept = table.filter(pa.array(times <= resume_time)).cast(self._schema)
        # Merged file first, then drop the parts: a crash in between leaves the dropped
        # rows readable again, and the next resume drops them again.
        with atomic_path(self.path) as tmp:
            pq.write_table(kept, tmp)
        shutil.rmtree(self._parts, ignore_errors=True)
        if self.csv_path is not None:
            self.csv_path.unlink(missing_ok=True)
        if kept.num_rows:
            self._last_time = kept.column(TIME_COLUMN)[-1].as_py()

    # -- writing

    @property
    def last_time(self) -> float:
        """Time of the last row appended (or kept on resume); ``-inf`` before any."""
        return self._last_time

    def append(self, rows: np.ndarray | Sequence[float]) -> None:
        """Append one row ``(ncols,)`` or a block ``(n, ncols)``; column 0 is time in s."""
        if self._closed:
            raise ValueError(f"history writer for {self.path} is closed")
        block = np.asarray(rows, dtype=np.float64)
        if block.ndim == 1:
            block = block[None, :]
        if block.ndim != 2 or block.shape[1] != len(self.columns):
            raise ValueError(
                f"history rows must have {len(self.columns)} columns, got shape {block.shape}"
            )
        if block.shape[0] == 0:
            return
        t = block[:, 0]
        if not (t[0] > self._last_time and np.all(t[1:] > t[:-1])):
            raise ValueError(
                f"history times must increase strictly: got {t[0]!r} after {self._last_time!r}"
            )
        self._last_time = float(t[-1])
        if self._n_buffered == 0:
            self._buffer_since = time.monotonic()
        while block.shape[0]:
            take = min(self.chunk_rows - self._n_buffered, block.shape[0])
            self._buffer[self._n_buffered : self._n_buffered + take] = block[:take]
            self._n_buffered += take
            block = block[take:]
            if self._n_buffered == self.chunk_rows:
                self.flush()
                if block.shape[0]:
                    self._buffer_since = time.monotonic()
        if self._n_buffered and time.monotonic() - self._buffer_since > self.max_wall_s:
            self.flush()

    def flush(self) -> None:
        """Write the buffered rows (if any) as the next chunk part."""
        if self._n_buffered == 0:
            return
        data = self._buffer[: self._n_buffered]
        table = pa.Table.from_arrays(
            [pa.array(data[:, i]) for i in range(data.shape[1])], schema=self._schema
        )
        self._parts.mkdir(parents=True, exist_ok=True)
        with atomic_path(self._parts / f"part-{self._next_part:06d}.parquet") as tmp:
            pq.write_table(table, tmp)
        self._next_part += 1
        self._n_buffered = 0

    def close(self) -> Path:
        """Flush, merge the parts into the final file(s), remove the parts. Idempotent.

        Returns
        -------
        pathlib.Path
            The merged Parquet file.
        """
        if self._closed:
            return self.path
        self.flush()
        self._closed = True
        table = _read_on_disk(self.path)
        if table is None:
            table = self._schema.empty_table()
        with atomic_path(self.path) as tmp:
            pq.write_table(table, tmp)
        if self.csv_path is not None:
            with atomic_path(self.csv_path) as tmp:
                table.to_pandas().to_csv(tmp, index=False, float_format="%.17g")
        shutil.rmtree(self._parts, ignore_errors=True)
        return self.path

    def __enter__(self) -> HistoryWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        # Also on an exception or KeyboardInterrupt: keep everything recorded so far.
        self.close()
