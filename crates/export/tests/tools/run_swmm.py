"""Runs an EPA SWMM 5 model with the real engine (PyPI `swmm-toolkit`) to its end and prints,
as JSON: the flow-routing continuity error (%), the steady inflow of every outfall over the
last tenth of the run (m³/s, time-weighted mean), the same over the tenth before it and the
range over the last tenth (both show whether the run reached its steady state), and the
warning and error lines of the report.

Usage: run_swmm.py MODEL.inp OUTFALL [OUTFALL ...]
"""
import json
import os
import sys
import tempfile

from swmm.toolkit import solver
from swmm.toolkit.shared_enum import NodeResult, ObjectType

model, outfalls = sys.argv[1], sys.argv[2:]
folder = tempfile.mkdtemp()
report, output = os.path.join(folder, "model.rpt"), os.path.join(folder, "model.out")
solver.swmm_open(model, report, output)
solver.swmm_start(True)
indices = {name: solver.project_get_index(ObjectType.NODE, name) for name in outfalls}
history = []
elapsed = 0.0
while True:
    now = solver.swmm_step()
    if now <= 0:
        break
    flows = {n: solver.node_get_result(i, NodeResult.TOTAL_INFLOW) for n, i in indices.items()}
    history.append((now - elapsed, now, flows))
    elapsed = now


def window(start, end):
    return [h for h in history if start * elapsed < h[1] <= end * elapsed]


def mean(steps, name):
    return sum(h[0] * h[2][name] for h in steps) / sum(h[0] for h in steps)


last, before = window(0.9, 1.0), window(0.8, 0.9)
solver.swmm_end()
continuity = solver.swmm_get_mass_balance()[1]
solver.swmm_report()
solver.swmm_close()
with open(report) as f:
    notes = [line.strip() for line in f if "WARNING" in line or "ERROR" in line]
for name in os.listdir(folder):
    os.remove(os.path.join(folder, name))
os.rmdir(folder)
print(json.dumps({
    "continuity_error": continuity,
    "outfalls": {n: mean(last, n) for n in outfalls},
    "outfalls_before": {n: mean(before, n) for n in outfalls},
    "outfalls_range": {n: [min(h[2][n] for h in last), max(h[2][n] for h in last)] for n in outfalls},
    "notes": notes,
}))
