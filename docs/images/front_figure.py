"""The README's picture: the FRF of examples/systems/liftoff3.toml (a contact that sticks,
slips and lifts off) coloured by the contact's state over each point's period.

    python3 docs/images/front_figure.py [HBF] [OUT.png]

HBF is the hbf executable (default build/hbf), OUT the figure (default docs/images/frf_states.png).
"""
import csv
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
hbf = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build", "hbf")
out = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "docs", "images", "frf_states.png")
system = os.path.join(root, "examples", "systems", "liftoff3.toml")

with tempfile.TemporaryDirectory() as tmp:
    table = os.path.join(tmp, "frf.csv")
    subprocess.run([hbf, "frf", "--config", system, "--out", table, "--quiet"], check=True)
    rows = [r for r in csv.DictReader(open(table)) if r["point"] != "sample"]


def state(row):
    """stuck, stick-slip or lift-off: what the contact does over the point's period."""
    if float(row["separated_fraction"]) > 0.0:
        return "lift-off"
    return "stuck" if float(row["stick_fraction"]) >= 1.0 else "stick-slip"


colours = {"stuck": "#1f77b4", "stick-slip": "#ff7f0e", "lift-off": "#2ca02c"}
fig, ax = plt.subplots(figsize=(7.0, 3.6), dpi=110)
shown = set()
for a, b in zip(rows, rows[1:]):
    if a["branch"] != b["branch"]:
        continue
    s = state(b)
    ax.plot([float(a["w"]), float(b["w"])], [float(a["y1_max"]), float(b["y1_max"])], color=colours[s], lw=2,
            label=None if s in shown else s)
    shown.add(s)
ax.set_xlabel("excitation frequency w")
ax.set_ylabel("max |y1(t)| over a period")
ax.set_title("hbf frf --config examples/systems/liftoff3.toml", fontsize=10)
ax.legend(title="the contact over the period", fontsize=9, title_fontsize=9)
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(out)
print(out)
