"""Reads a rapier-kjoint .rrd recording back with the rerun SDK (rerun-sdk==0.36.3).

Usage: python read_rrd.py FILE.rrd [ENTITY_PATH ...]

Prints JSON: {"entities": [every entity path], "last": {path: {"time": sim_time [s],
"value": scalar}} for the given paths (the value at the largest sim_time),
"events": [TextLog texts of /events in time order],
"blueprints": [{entity path: {column: value}} of each blueprint store in the file]}.
A blueprint value is the last row's cell of that column (a list: one entry per instance),
with bytes (UUIDs) as hex strings.
"""

import json
import sys

import pyarrow as pa
from rerun.experimental import RrdReader


def column_ints(batch, name):
    col = batch.column(batch.schema.get_field_index(name))
    return col.cast(pa.int64()).to_pylist()


def plain(v):
    """`v` with its bytes as hex strings (JSON has no bytes)."""
    if isinstance(v, bytes):
        return v.hex()
    if isinstance(v, list):
        return [plain(x) for x in v]
    if isinstance(v, dict):
        return {k: plain(x) for k, x in v.items()}
    return v


def blueprint(reader, store):
    """{entity path: {column: last row's cell}} of one blueprint store."""
    out = {}
    for chunk in reader.stream(store=store).to_chunks():
        batch = chunk.to_record_batch()
        row = batch.num_rows - 1
        if row < 0:
            continue
        cells = out.setdefault(chunk.entity_path, {})
        for name in batch.schema.names:
            if ":" in name:  # components, as `Archetype:field`
                cells[name] = plain(batch.column(batch.schema.get_field_index(name))[row].as_py())
    return out


def main():
    path, wanted = sys.argv[1], sys.argv[2:]
    entities = set()
    last = {}
    events = []
    for chunk in RrdReader(path).stream().to_chunks():
        entity = chunk.entity_path
        entities.add(entity)
        batch = chunk.to_record_batch()
        names = batch.schema.names
        if "sim_time" not in names:
            continue
        times = [t / 1e9 for t in column_ints(batch, "sim_time")]
        if entity in wanted and "Scalars:scalars" in names:
            values = batch.column(names.index("Scalars:scalars")).to_pylist()
            for t, v in zip(times, values):
                if v and (entity not in last or t >= last[entity]["time"]):
                    last[entity] = {"time": t, "value": v[0]}
        if entity == "/events" and "TextLog:text" in names:
            texts = batch.column(names.index("TextLog:text")).to_pylist()
            events.extend((t, x[0]) for t, x in zip(times, texts) if x)
    events.sort()
    reader = RrdReader(path)
    blueprints = [blueprint(reader, store) for store in reader.blueprints()]
    json.dump(
        {
            "entities": sorted(entities),
            "last": last,
            "events": [x for _, x in events],
            "blueprints": blueprints,
        },
        sys.stdout,
    )


if __name__ == "__main__":
    main()
