#!/usr/bin/env python3
"""Measured (Welch) against Dryden PSD of the simulator's gusts, as a PNG and a table.

usage: plot_turbulence_psd.py TURBULENCE_SERIES OUT.png [INTENSITY [SEED]]
TURBULENCE_SERIES is devel/lib/aar_sim/turbulence_series. Numpy only (an implementation of its
own, independent of the C++ test's): Hann window, 2^15-sample segments, half overlapping.
"""
import subprocess
import sys
import tempfile

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def welch(x, n, dt):
    w = np.hanning(n + 1)[:-1]  # periodic Hann, as the C++ test
    segs = [x[s:s + n] for s in range(0, len(x) - n + 1, n // 2)]
    p = np.zeros(n // 2 + 1)
    for s in segs:
        p += np.abs(np.fft.rfft((s - s.mean()) * w)) ** 2
    p *= 2.0 * dt / (np.sum(w * w) * len(segs))  # one-sided, per Hz
    return np.fft.rfftfreq(n, dt), p


def main():
    if len(sys.argv) < 3 or len(sys.argv) > 5:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    tool, png = sys.argv[1], sys.argv[2]
    intensity = sys.argv[3] if len(sys.argv) > 3 else "moderate"
    seed = sys.argv[4] if len(sys.argv) > 4 else "3"
    steps = 1 << 21
    with tempfile.NamedTemporaryFile(suffix=".bin") as f:
        out = subprocess.run([tool, intensity, seed, str(steps), f.name], check=True,
                             capture_output=True, text=True).stdout.split()
        sigma, L, V, dt = (float(v) for v in out)
        x = np.fromfile(f.name, dtype="<f8").reshape(-1, 3)
    n = 1 << 15
    om = lambda f: 2 * np.pi * f * L / V  # noqa: E731
    dryden_u = lambda f: 2 * np.pi * sigma**2 * 2 * L / (np.pi * V) / (1 + om(f)**2)  # noqa
    dryden_vw = lambda f: (2 * np.pi * sigma**2 * L / (np.pi * V) * (1 + 3 * om(f)**2)  # noqa
                           / (1 + om(f)**2)**2)
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    print(f"{intensity}, seed {seed}: sigma {sigma:.3f} m/s, L {L} m, V {V} m/s, "
          f"{steps} steps of {dt} s")
    for i, (name, model, colour) in enumerate(
            [("u", dryden_u, "C0"), ("v", dryden_vw, "C1"), ("w", dryden_vw, "C2")]):
        f, p = welch(x[:, i], n, dt)
        keep = f > 0
        ax.loglog(f[keep], p[keep], colour, lw=0.6, alpha=0.7, label=f"{name} measured")
        if name != "w":  # v and w share the form
            ax.loglog(f[keep], model(f[keep]), "k" + ("--" if name == "u" else ":"), lw=1.2,
                      label="Dryden u" if name == "u" else "Dryden v, w")
        edges = np.geomspace(3 / (n * dt), 5.0, 15)
        ratios = []
        for lo, hi in zip(edges[:-1], edges[1:]):
            band = (f >= lo) & (f < hi)
            ratios.append(p[band].sum() / model(f[band]).sum())
        print(f"  {name}: variance/sigma^2 {x[:, i].var() / sigma**2:.4f}; band ratios "
              f"{min(ratios):.3f} to {max(ratios):.3f}")
    ax.set_xlim(3 / (n * dt), 50)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD [(m/s)$^2$/Hz]")
    ax.set_title(f"Gust PSD, {intensity} ({sigma:.2f} m/s), V {V:.0f} m/s, L {L:.1f} m",
                 fontsize=10)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(png)
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
