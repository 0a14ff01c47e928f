"""The tutorial's Python steps: the same system file, FRF, nonlinear mode and peak tracking as
the command line, read back as NumPy columns and drawn with matplotlib (writes bar/python.png)."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import numpy as np  # noqa: E402

import hbfriction  # noqa: E402

# [steps]
system = hbfriction.load("bar/bar.toml")      # reduced on loading, as hbf frf --config does
print(system.dofs, "coordinates,", len(system.contacts), "contacts")
branch = hbfriction.frf(system)               # the file's frequency range and harmonics
print(branch)                                 # status and size
print("peak of mid:", branch.peak)            # the refined largest peak of the first output
face = branch.interface_states("end face")    # node-averaged shares stuck / slipping / open
mode = hbfriction.modes(system, 4e-8, 6e-7)  # the first stuck mode (mode_index=0)
print(mode)
# [/steps]
# [track]
force = np.asarray(system.excitation)       # the file's force, on the reduced coordinates


def bar_at(fe):                               # the system at a factor fe on the force
    s = hbfriction.load("bar/bar.toml")
    s.excitation = force * fe
    return s


peak = hbfriction.track(bar_at, 0.3, 0.9, harmonics=3)   # as hbf track --param fe
print(peak.curves[0])                         # the peak's curve: p, w, value
# [/track]
# [plot]
fig, (top, middle, bottom, last) = plt.subplots(4, 1, figsize=(7, 10.5))
top.plot(branch.w, branch.mid_max, label="FRF (harmonic balance)")
top.plot(mode.w, mode.mid_max, "--", label="backbone (nonlinear mode)")
top.set_ylabel("mid_max [m]")
top.legend()
middle.plot(branch.w, face["stuck_share"], label="stuck")
middle.plot(branch.w, face["slip_share"], label="slipping")
middle.plot(branch.w, face["open_share"], label="open")
middle.set_xlabel("w [rad/s]")
middle.set_ylabel("share of the period")
middle.legend()
bottom.semilogx(mode.a, 100 * mode.zeta)
bottom.set_xlabel("modal amplitude a")
bottom.set_ylabel("modal damping ratio [%]")
last.plot(peak.curves[0].p, peak.curves[0].w)
last.set_xlabel("force factor fe")
last.set_ylabel("peak frequency [rad/s]")
fig.tight_layout()
fig.savefig("bar/python.png")
# [/plot]
