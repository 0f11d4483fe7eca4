"""The Campbell diagram of a rotating body: its frequencies against speed (from epaphe-campbell's
HDF5 table), the engine-order lines f = k Omega / (2 pi), and where they cross."""
import numpy as np


def crossings(speeds, frequencies, orders):
    """Every crossing of a frequency curve with an engine-order line over the sampled speeds.

    Parameters
    ----------
    speeds : array (N,), rad/s, ascending
    frequencies : array (N, K), Hz; column i is mode i + 1 (NaN where absent)
    orders : iterable of int, the engine orders k

    Returns
    -------
    list of (speed_rad_s, order, mode, frequency_hz), sorted by speed: where f_i(Omega) - k Omega / 2 pi
    changes sign between two sampled speeds, located by linear interpolation of that difference.
    """
    speeds = np.asarray(speeds, dtype=float)
    out = []
    for k in orders:
        line = k * speeds / (2 * np.pi)
        for i in range(frequencies.shape[1]):
            d = frequencies[:, i] - line
            for j in range(len(speeds) - 1):
                a, b = d[j], d[j + 1]
                if not (np.isfinite(a) and np.isfinite(b)) or a == 0 and j > 0:
                    continue
                if a == 0 or a * b < 0:
                    t = 0.0 if a == 0 else a / (a - b)
                    w = speeds[j] + t * (speeds[j + 1] - speeds[j])
                    out.append((float(w), int(k), i + 1, float(k * w / (2 * np.pi))))
    return sorted(out)


def draw(table, orders, title, path, peer=None):
    """The diagram: each mode's curve, the full model's frequencies at the sample speeds (and between)
    as points, the engine-order lines and the crossings circled. `table`: dict with speeds,
    frequencies, full_speeds, full_frequencies; `peer`: optional (speeds, frequencies, label) drawn as
    crosses (another code's points)."""
    import matplotlib.pyplot as plt

    speeds, freq = table["speeds"], table["frequencies"]
    fig, ax = plt.subplots(figsize=(8, 6))
    for i in range(freq.shape[1]):
        ax.plot(speeds, freq[:, i], "-", color="C0", lw=1.2, label="reduced model (parametric)" if i == 0 else None)
    fs, ff = table["full_speeds"], table["full_frequencies"]
    for i in range(ff.shape[1]):
        ax.plot(fs, ff[:, i], "o", mfc="none", color="C3", ms=6, label="full model at speed" if i == 0 else None)
    if peer is not None:
        ps, pf, label = peer
        for i in range(pf.shape[1]):
            ax.plot(ps, pf[:, i], "x", color="k", ms=7, label=label if i == 0 else None)
    top = np.nanmax(freq) * 1.05
    for k in orders:
        ax.plot(speeds, k * speeds / (2 * np.pi), "--", color="0.6", lw=0.8)
        w_end = min(speeds[-1], 2 * np.pi * top / k)
        ax.annotate(f"EO {k}", (w_end, k * w_end / (2 * np.pi)), fontsize=7, color="0.4")
    for w, k, mode, f in crossings(speeds, freq, orders):
        ax.plot([w], [f], "s", mfc="none", color="C2", ms=7)
    ax.set_xlim(speeds[0], speeds[-1])
    ax.set_ylim(0, top)
    ax.set_xlabel("rotation speed (rad/s)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(title, fontsize=10)
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
