"""Runs an EPA SWMM 5 model with the real engine (PyPI `swmm-toolkit`) to its end and prints,
as JSON: the flow-routing continuity error (%), the steady inflow of every outfall (m³/s: its
time-weighted mean over the last quarter of the run, which smooths the solver's oscillations),
and the warning and error lines of the report.

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
    history.append((now - elapsed, now, {n: solver.node_get_result(i, NodeResult.TOTAL_INFLOW) for n, i in indices.items()}))
    elapsed = now
tail = [h for h in history if h[1] >= 0.75 * elapsed]
weight = sum(h[0] for h in tail)
flows = {n: sum(h[0] * h[2][n] for h in tail) / weight for n in outfalls}
solver.swmm_end()
continuity = solver.swmm_get_mass_balance()[1]
solver.swmm_report()
solver.swmm_close()
with open(report) as f:
    notes = [line.strip() for line in f if "WARNING" in line or "ERROR" in line]
print(json.dumps({"continuity_error": continuity, "outfalls": flows, "notes": notes}))
