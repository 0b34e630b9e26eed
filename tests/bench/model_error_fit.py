#!/usr/bin/env python3
"""Fits the model error's three weights (lib/bake/model_error.h) on the study rows.

  tests/bench/model_error_fit.py RESULTS_DIR

Reads RESULTS_DIR/sun_predicted.csv (sun_study) and RESULTS_DIR/concavity.csv (concavity_study),
whose model_* columns are the bake's terms at the weights in model_error.h, so that the features
are model_* / weight. Chooses the weights that minimize the worst |log(measured / predicted)| over
every row (predicted = sqrt(numerical^2 + sum (weight * feature)^2)), prints them with each row's
ratio and the leave-one-out ratios (each row predicted with weights fitted without it), and writes
RESULTS_DIR/model_error.csv. Pure Python, a few seconds.
"""
import csv
import math
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
NAMES = ("kExitModelWeight", "kFacetWeight", "kFacetLightWeight")
COLUMNS = ("model_exit", "model_facets", "model_facet_light")


def current_weights():
    text = (ROOT / "lib/bake/model_error.h").read_text()
    return [float(re.search(name + r" = ([0-9.]+);", text).group(1)) for name in NAMES]


def load_rows(results):
    rows = []
    for r in csv.DictReader(open(results / "sun_predicted.csv")):
        rows.append((r["scene"], float(r["rms_vertex_L"]), r))
    for r in csv.DictReader(open(results / "concavity.csv")):
        rows.append((r["scene"] + "-bounces-" + r["bounces_asked"], float(r["rms_all"]), r))
    weights = current_weights()
    out = []
    for name, measured, r in rows:
        features = [float(r[c]) / w for c, w in zip(COLUMNS, weights)]
        out.append((name, measured, float(r["numerical"]), features))
    return out


def predicted(row, weights):
    _, _, numerical, features = row
    return math.sqrt(numerical**2 + sum((w * f) ** 2 for w, f in zip(weights, features)))


def grid():
    for a in range(31):
        for b in range(41):
            for c in range(41):
                yield (0.05 * a, 0.025 * b, 0.025 * c)


def fit(rows):
    best = None
    for weights in grid():
        worst = max(abs(math.log(m / predicted(r, weights))) for r in rows for m in [r[1]])
        if best is None or worst < best[0]:
            best = (worst, weights)
    return best


def main():
    results = Path(sys.argv[1] if len(sys.argv) > 1 else ROOT / "tests/bench/results/accuracy")
    rows = load_rows(results)
    worst, weights = fit(rows)
    print("weights exit %.3f facets %.3f light %.3f: worst ratio %.2f" % (*weights, math.exp(worst)))
    with open(results / "model_error.csv", "w") as f:
        f.write("scene,measured,numerical,predicted,measured_over_predicted,"
                "measured_over_numerical,leave_one_out_ratio\n")
        for i, row in enumerate(rows):
            others = rows[:i] + rows[i + 1:]
            loo = row[1] / predicted(row, fit(others)[1])
            p = predicted(row, weights)
            f.write("%s,%.5f,%.5f,%.5f,%.2f,%.2f,%.2f\n" %
                    (row[0], row[1], row[2], p, row[1] / p, row[1] / row[2], loo))
            print("%-34s measured %.4f predicted %.4f (%.2fx; numerical only %.2fx; "
                  "left out %.2fx)" % (row[0], row[1], p, row[1] / p, row[1] / row[2], loo))


if __name__ == "__main__":
    main()
