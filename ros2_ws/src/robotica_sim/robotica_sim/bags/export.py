"""
A recorded run's time series as tables: one per topic, one row per message, flattened fields.

What ``robotica export`` writes, for a spreadsheet or pandas. Each row starts with ``t``, the
message's receive time in the bag [s] (simulated time in a ``robotica run`` bag). Fields are
flattened into columns named by their path (``pose.pose.position.x``):

* a ``builtin_interfaces/Time`` or ``Duration`` (``header.stamp``) is one column of float
  seconds;
* an array of numbers of at most ``MAX_EXPANDED`` elements is one column per element
  (``pose.covariance.0`` … ``.35``, ``position.0`` …), a variable-length array as long as its
  longest message (shorter messages leave the rest empty);
* a longer array, and an array of messages (``nav_msgs/Path`` poses, ``tf2_msgs/TFMessage``
  transforms), is one column holding JSON (the array's elements flattened the same way), so
  that a table keeps one row per message.

CSV (``csv`` module, floats written in full precision, empty cells for missing values) or
Apache Parquet (``pyarrow``, nulls for missing values). The bag is opened with
:func:`robotica_sim.bags.info.open_bag` (partial and damaged bags are refused with its message).
"""
import csv
from dataclasses import dataclass
import json
from pathlib import Path
from typing import Any, Iterable

import numpy as np
from robotica_sim.bags.info import open_bag

__all__ = ['EXPORT_FORMATS', 'ExportedTable', 'ExportError', 'MAX_EXPANDED', 'export_bag',
           'flatten', 'table_name']

EXPORT_FORMATS = ('csv', 'parquet')
MAX_EXPANDED = 64   # elements of an array of numbers given one column each (a covariance: 36)
_TIME_TYPES = ('builtin_interfaces/msg/Time', 'builtin_interfaces/msg/Duration')


class ExportError(ValueError):
    """A request that cannot be exported: an unknown topic, an output that exists."""


@dataclass(frozen=True)
class ExportedTable:
    """One topic written as a table: its file, rows and columns."""

    topic: str
    path: Path
    rows: int
    columns: int


def table_name(topic: str) -> str:
    """
    Return the file stem of ``topic``'s table: its name without the leading slash, '.' for '/'.

    >>> table_name('/ground_truth/odom')
    'ground_truth.odom'
    """
    return topic.strip('/').replace('/', '.') or 'root'


def _is_message(value: Any) -> bool:
    return hasattr(value, '__msgtype__')


def _plain(value: Any) -> Any:
    """Return ``value`` (a field) as JSON-able data: messages as flattened dicts."""
    if _is_message(value):
        return flatten(value)
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, bytes):
        return list(value)
    if isinstance(value, np.generic):
        return value.item()
    return value


def flatten(msg: Any, prefix: str = '') -> dict[str, Any]:
    """
    Return the fields of a rosbags message as one flat dict (see the module's rules).

    >>> from rosbags.typesys import get_typestore, Stores
    >>> types = get_typestore(Stores.ROS2_JAZZY).types
    >>> Time = types['builtin_interfaces/msg/Time']
    >>> header = types['std_msgs/msg/Header'](stamp=Time(sec=3, nanosec=500_000_000),
    ...                                       frame_id='odom')
    >>> flatten(header)
    {'stamp': 3.5, 'frame_id': 'odom'}
    """
    if msg.__msgtype__ in _TIME_TYPES:
        return {prefix.rstrip('.') or 'time': msg.sec + msg.nanosec * 1e-9}
    row: dict[str, Any] = {}
    for name in msg.__dataclass_fields__:
        if name.startswith('__'):   # rosbags' __msgtype__
            continue
        value = getattr(msg, name)
        key = prefix + name
        if _is_message(value):   # a Time or Duration comes back as {key: seconds}
            row.update(flatten(value, key + '.'))
        elif isinstance(value, np.ndarray) and value.ndim == 1 and value.dtype.kind in 'biuf' \
                and value.size <= MAX_EXPANDED:
            row.update({f'{key}.{i}': v for i, v in enumerate(value.tolist())})
        elif isinstance(value, (np.ndarray, list, tuple, bytes)):
            row[key] = json.dumps(_plain(value))
        else:
            row[key] = _plain(value)
    return row


def _columns(rows: list[dict[str, Any]]) -> list[str]:
    """Return the union of the rows' keys, in the order they first appear."""
    seen: dict[str, None] = {}
    for row in rows:
        seen.update(dict.fromkeys(row))
    return list(seen)


def _write_csv(path: Path, columns: list[str], rows: list[dict[str, Any]]) -> None:
    with open(path, 'x', newline='') as stream:
        writer = csv.DictWriter(stream, fieldnames=columns, restval='')
        writer.writeheader()
        writer.writerows(rows)


def _write_parquet(path: Path, columns: list[str], rows: list[dict[str, Any]]) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq
    table = pa.table({name: [row.get(name) for row in rows] for name in columns})
    with open(path, 'xb') as stream:
        pq.write_table(table, stream)


def export_bag(bag: str | Path, output: str | Path, fmt: str = 'csv',
               topics: Iterable[str] | None = None) -> list[ExportedTable]:
    """
    Write each topic of ``bag`` (or of ``topics``) as a table into the directory ``output``.

    Returns the tables written, in topic order.

    Raises
    ------
    ExportError
        For an unknown format or topic, or a table file that exists in ``output``.
    robotica_sim.bags.info.BagError
        If ``bag`` cannot be read (see :func:`robotica_sim.bags.info.open_bag`).

    """
    if fmt not in EXPORT_FORMATS:
        raise ExportError(f'format must be one of {", ".join(EXPORT_FORMATS)}, got {fmt!r}')
    output = Path(output)
    write = _write_csv if fmt == 'csv' else _write_parquet
    reader = open_bag(bag)
    try:
        recorded = sorted({c.topic for c in reader.connections})
        wanted = recorded if topics is None else list(dict.fromkeys(topics))
        unknown = [t for t in wanted if t not in recorded]
        if unknown:
            raise ExportError(f'{", ".join(unknown)} not in {bag}; its topics: '
                              f'{", ".join(recorded)}')
        targets = {t: output / f'{table_name(t)}.{fmt}' for t in wanted}
        existing = [str(p) for p in targets.values() if p.exists()]
        if existing:
            raise ExportError(f'{", ".join(existing)} exists already: choose another --output')
        rows: dict[str, list[dict[str, Any]]] = {t: [] for t in wanted}
        connections = [c for c in reader.connections if c.topic in rows]
        for connection, timestamp, raw in reader.messages(connections=connections):
            message = reader.deserialize(raw, connection.msgtype)
            rows[connection.topic].append({'t': timestamp * 1e-9, **flatten(message)})
    finally:
        reader.close()
    output.mkdir(parents=True, exist_ok=True)
    tables = []
    for topic, path in targets.items():
        columns = _columns(rows[topic]) or ['t']
        write(path, columns, rows[topic])
        tables.append(ExportedTable(topic, path, len(rows[topic]), len(columns)))
    return tables
