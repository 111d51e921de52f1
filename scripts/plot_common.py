"""What the plot scripts share (plot_raytrace.py, plot_realistic.py, plot_sixdof.py): matplotlib without a
display, each detector's label, colour and line style, and the PNG written to a temporary and renamed."""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STYLE = {  # detector: (label, colour, line style)
    "tagbench": ("ours (default profile), full resolution", "tab:purple", "-"),
    "tagbench-half": ("ours (default profile), half resolution", "tab:pink", "--"),
    "tagbench-thorough": ("ours (thorough profile: full-resolution line quads)", "tab:brown", "-."),
    "tagbench-paper": ("ours (paper profile), full resolution", "tab:blue", "-"),
    "tagbench-paper-half": ("ours (paper profile), half resolution", "tab:cyan", "--"),
    "libapriltag-d1": ("libapriltag 3.3, decimate 1", "tab:orange", "-"),
    "libapriltag-d2": ("libapriltag 3.3, decimate 2", "tab:red", "--"),
    "aruco": ("OpenCV 4.6 aruco (APRILTAG refine)", "tab:green", "-"),
}
MIN_DETECTED_FOR_ERRORS = 3


def number(s):
    return float(s) if s not in ("", None) else math.nan


def detectors_in(rows):
    seen = []
    for r in rows:
        if r["detector"] not in seen:
            seen.append(r["detector"])
    return seen


def style(detector):
    return STYLE.get(detector, (detector, None, "-"))


def save(fig, out):
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=100)
    plt.close(fig)
    os.replace(tmp, out)
