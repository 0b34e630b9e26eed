#!/usr/bin/env python3
"""Gathers the workflow's JSON reports into one CSV: a line per manifest row, the bake's and the
render's reports flattened (bake.stages.tool_total_s, render.times_ms.total, ...) and the report
of sss-irrmap on the row's environment (irrmap.method, ...), matched through the radiance cubemap
the bake read. Lists are joined with ';'. Written to a temporary name and renamed."""
import argparse
import csv
import json
import os


def flatten(value, prefix, out):
    if isinstance(value, dict):
        for key, item in value.items():
            flatten(item, f"{prefix}.{key}" if prefix else key, out)
    elif isinstance(value, list):
        out[prefix] = ";".join(json.dumps(v) if isinstance(v, (dict, list)) else str(v) for v in value)
    else:
        out[prefix] = value
    return out


def load(path):
    with open(path) as f:
        return json.load(f)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", required=True)
    p.add_argument("--rows", nargs="+", required=True)
    p.add_argument("--bake", nargs="+", required=True)
    p.add_argument("--render", nargs="+", required=True)
    p.add_argument("--irrmap", nargs="*", default=[])
    a = p.parse_args()
    if not len(a.rows) == len(a.bake) == len(a.render):
        p.error("--rows, --bake and --render need one entry per row")
    by_radiance = {}
    for path in a.irrmap:
        report = load(path)
        radiance = report.get("outputs", {}).get("radiance")
        if radiance:
            by_radiance[os.path.normpath(radiance)] = report
    lines, columns = [], ["name"]
    for name, bake_path, render_path in zip(a.rows, a.bake, a.render):
        bake = load(bake_path)
        line = {"name": name}
        flatten(bake, "bake", line)
        flatten(load(render_path), "render", line)
        source = os.path.normpath(bake.get("environment", {}).get("source", ""))
        if source in by_radiance:
            flatten(by_radiance[source], "irrmap", line)
        lines.append(line)
        columns += [c for c in line if c not in columns]
    temporary = a.out + ".tmp"
    with open(temporary, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(lines)
    os.replace(temporary, a.out)


if __name__ == "__main__":
    main()
