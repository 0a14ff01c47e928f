"""The tutorial's Python steps: the same sector, its nodal-diameter families, FRF and nonlinear
mode from Python, and the damper's design curve read from hbf map's summary, drawn with
matplotlib (writes wheel/python.png)."""
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import hbfriction  # noqa: E402

# [steps]
sector = hbfriction.load("wheel/sector.toml")  # reduced on loading, the cut faces kept
print(sector.dofs, "coordinates;", sector.cyclic)  # sectors, engine order, the next sector's DOFs
families = hbfriction.nodal_diameters(sector)    # released and stuck, per nodal diameter
branch = hbfriction.frf(sector)                  # engine order 3, the file's band
print("peak of the tip:", branch.peak)
mode = hbfriction.modes(sector)                  # the first mode of nodal diameter 3
print(mode.linear["omega"], mode.linear["shape"][:4])  # a travelling wave: a complex shape
# [/steps]
# [plot]
with open("wheel/load.json") as f:
    load = json.load(f)
slip = load["parameter"]["values"]
peaks = [r["peak"] for r in load["frfs"]]
first = families.mode == 1
fig, axes = plt.subplots(2, 2, figsize=(10, 7.5))
ax = axes[0][0]
ax.plot(families.nodal_diameter[first], families.released[first], "o-", label="released")
ax.plot(families.nodal_diameter[first], families.stuck[first], "s-", label="stuck")
ax.axvline(3, color="grey", linestyle=":", label="engine order 3")
ax.set_xlabel("nodal diameter")
ax.set_ylabel("first family's frequency [rad/s]")
ax.legend()
ax = axes[0][1]
ax.plot(branch.w, branch.y66_max, label="FRF (harmonic balance)")
ax.plot(mode.w, mode.y66_max, "--", label="backbone (nonlinear mode)")
ax.set_xlabel("w [rad/s]")
ax.set_ylabel("blade tip u_t, max over a period [m]")
ax.set_ylim(0.0, 1.5 * branch.y66_max.max())  # the backbone goes on to the slipping mode's large amplitudes
ax.legend()
ax = axes[1][0]
ax.loglog(slip, peaks, "o-")
ax.set_xlabel("damper slip force mu N [N]")
ax.set_ylabel("peak of the blade tip [m]")
ax = axes[1][1]
ax.semilogx(mode.a, 100 * mode.zeta)
ax.set_xlabel("modal amplitude a")
ax.set_ylabel("modal damping ratio [%]")
fig.tight_layout()
fig.savefig("wheel/python.png")
# [/plot]
