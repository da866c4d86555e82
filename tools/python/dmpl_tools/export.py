"""tools/dmpl export LOG [--format parquet|csv] [--channels REGEX] [--out DIR]

Writes one table per channel of an LCM log (DIR/<CHANNEL>.parquet or .csv; controller events as
<CHANNEL>.events): a row per message with utime, seq and every field flattened into columns of
numbers or strings (object_position_x, tactile_force_T, tactile_position_T_x, joint_position_T_j0,
...). pandas (`pd.read_parquet`) and polars (`pl.read_parquet`) read them directly.

The channels tools read (sensors, controller status and report, supervisor status, tasks, sim
status and control) come from dmpl_logcols in one C++ pass; any other channel is decoded here
with its generated Python type (found by the message's fingerprint), a batch at a time, so memory
stays bounded whatever the log's length. Messages that cannot be decoded are counted and skipped.
"""
import argparse
import re
import struct
import sys
import tempfile
from pathlib import Path

from .logdata import Columns, LogError, extract

BATCH = 20000
# Fields that are one vector (or quaternion) per row; every other 2-D field has a value per
# finger (or per joint: joint_*), and every 3-D field a vector per finger.
VECTOR_FIELDS = {"object_position", "object_orientation", "object_linear_velocity",
                 "object_angular_velocity", "contact_centroid"}


def _axis_labels(size):
    return list({3: "xyz", 4: "wxyz"}.get(size, [str(i) for i in range(size)]))


def _labels(field, size, fingers, joints):
    if field in VECTOR_FIELDS:
        return _axis_labels(size)
    names = joints if field.startswith("joint_") else fingers
    return list(names) if len(names) == size else [str(i) for i in range(size)]


def flatten_columns(table, fingers, joints):
    """{field: array (n, ...)} -> {column: 1-D array}, naming the dimensions."""
    out = {}
    for field in (["utime", "seq"] + sorted(k for k in table if k not in ("utime", "seq"))):
        if field not in table:
            continue
        a = table[field]
        if a.ndim == 1:
            out[field] = a
        elif a.ndim == 2:
            for i, label in enumerate(_labels(field, a.shape[1], fingers, joints)):
                out[f"{field}_{label}"] = a[:, i]
        elif a.ndim == 3:
            outer = _labels(field, a.shape[1], fingers, joints)
            inner = _axis_labels(a.shape[2])
            for i, lo in enumerate(outer):
                for j, li in enumerate(inner):
                    out[f"{field}_{lo}_{li}"] = a[:, i, j]
    return out


def flatten_message(msg, prefix="", out=None):
    """A decoded lcm-gen object -> {column: value}, nested structs and arrays flattened."""
    out = {} if out is None else out
    for slot in msg.__slots__:
        value = getattr(msg, slot)
        name = f"{prefix}{slot}"
        if isinstance(value, (list, tuple)):
            for i, v in enumerate(value):
                if hasattr(v, "__slots__"):
                    flatten_message(v, f"{name}_{i}_", out)
                else:
                    out[f"{name}_{i}"] = v
        elif hasattr(value, "__slots__"):
            flatten_message(value, f"{name}_", out)
        else:
            out[name] = value
    return out


def _types_by_fingerprint():
    import dmpl
    import importlib
    import pkgutil
    types = {}
    for info in pkgutil.iter_modules(dmpl.__path__):
        cls = getattr(importlib.import_module(f"dmpl.{info.name}"), info.name, None)
        if cls is not None and hasattr(cls, "_get_packed_fingerprint"):
            types[cls._get_packed_fingerprint()] = cls
    return types


class TableWriter:
    """Rows (dicts) -> one Parquet or CSV file, a batch at a time; the first batch fixes the
    columns (a later message with other fields fills what it lacks with nulls)."""

    def __init__(self, path, fmt):
        self.path, self.fmt = path, fmt
        self.writer, self.schema, self.rows = None, None, 0

    def write(self, columns):
        import pyarrow as pa
        if not columns:
            return
        table = pa.table({k: pa.array(v) for k, v in columns.items()})
        if self.schema is None:
            self.schema = table.schema
            if self.fmt == "parquet":
                import pyarrow.parquet as pq
                self.writer = pq.ParquetWriter(self.path, self.schema)
            else:
                import pyarrow.csv as pcsv
                self.writer = pcsv.CSVWriter(self.path, self.schema)
        else:
            cols = [table[n] if n in table.column_names else pa.nulls(len(table), f.type)
                    for n, f in zip(self.schema.names, self.schema)]
            table = pa.table(cols, schema=self.schema)
        self.writer.write_table(table)
        self.rows += len(table)

    def close(self):
        if self.writer is not None:
            self.writer.close()


def _write_table(path, fmt, columns):
    w = TableWriter(path, fmt)
    try:
        for start in range(0, len(next(iter(columns.values()), [])), BATCH):
            w.write({k: v[start:start + BATCH] for k, v in columns.items()})
    finally:
        w.close()
    return w.rows


def _strings(a):
    return [str(x) for x in a] if a.dtype == object else a


def export(log_path, out_dir, fmt="parquet", channels=".*"):
    """Writes the tables; returns {table name: rows} and a list of problems."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ext = "parquet" if fmt == "parquet" else "csv"
    written, problems = {}, []
    with tempfile.TemporaryDirectory(prefix="dmpl-export-") as tmp:
        extract(log_path, tmp, None, channels)
        cols = Columns(tmp)
        problems += cols.problems()
        for channel, info in cols.channels.items():
            fingers, joints = info.get("fingers", []), info.get("joints", [])
            for sub, name in (("", channel), ("events", f"{channel}.events")):
                table = cols.table(channel, sub)
                if not table:
                    continue
                flat = {k: _strings(v) for k, v in flatten_columns(table, fingers, joints).items()}
                written[name] = _write_table(out_dir / f"{name}.{ext}", fmt, flat)
        others = [c for c in cols.meta.get("other_channels", {}) if re.match(channels, c)]
    if others:
        counts, bad = _export_generic(log_path, out_dir, ext, fmt, set(others))
        written.update(counts)
        problems += [f"{c}: {n} messages skipped (no dmpl type decodes them)"
                     for c, n in bad.items()]
    return written, problems


def _export_generic(log_path, out_dir, ext, fmt, wanted):
    """Channels without C++ columns: decoded by their Python type, a batch at a time."""
    import lcm
    types = _types_by_fingerprint()
    writers, batches, bad = {}, {}, {}
    log = lcm.EventLog(str(log_path), "r")
    try:
        for event in log:
            if event.channel not in wanted:
                continue
            cls = types.get(event.data[:8])
            try:
                row = flatten_message(cls.decode(event.data)) if cls else None
            except (ValueError, struct.error):
                row = None
            if row is None:
                bad[event.channel] = bad.get(event.channel, 0) + 1
                continue
            batch = batches.setdefault(event.channel, [])
            batch.append(row)
            if len(batch) >= BATCH:
                _flush(writers, batches, event.channel, out_dir, ext, fmt)
        for channel in list(batches):
            _flush(writers, batches, channel, out_dir, ext, fmt)
    finally:
        log.close()
        for w in writers.values():
            w.close()
    return {c: w.rows for c, w in writers.items()}, bad


def _flush(writers, batches, channel, out_dir, ext, fmt):
    rows = batches.pop(channel, [])
    if not rows:
        return
    writer = writers.setdefault(channel, TableWriter(out_dir / f"{channel}.{ext}", fmt))
    names = list(dict.fromkeys(k for r in rows for k in r))
    writer.write({k: [r.get(k) for r in rows] for k in names})


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl export", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log")
    ap.add_argument("--format", choices=("parquet", "csv"), default="parquet")
    ap.add_argument("--channels", default=".*", help="channels to export (a regex)")
    ap.add_argument("--out", help="output directory (default: LOG's directory/export)")
    args = ap.parse_args(argv)
    try:
        re.compile(args.channels)
    except re.error as e:
        print(f"dmpl export: --channels is not a valid regex: {e}", file=sys.stderr)
        return 2
    log = Path(args.log)
    if not log.is_file():
        print(f"dmpl export: no such log '{log}'", file=sys.stderr)
        return 2
    out = Path(args.out) if args.out else log.parent / "export"
    try:
        written, problems = export(log, out, args.format, args.channels)
    except (LogError, OSError) as e:
        print(f"dmpl export: {e}", file=sys.stderr)
        return 2
    for name, rows in sorted(written.items()):
        print(f"  {name:34s} {rows:8d} rows")
    for p in problems:
        print(f"  problem: {p}")
    print(f"export: {len(written)} tables in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
