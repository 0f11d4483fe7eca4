"""Nodal diameters of a bladed stage: the instances of one body ('Instances') decomposed into
travelling waves (docs/user/stage.md).

Blade k of N stands at theta_k = 2 pi k / N. A history x_k(t) of the same quantity on every blade
(a watched node's displacement, a contact force) is split over the instances by the spatial DFT

    X_n(t) = (1/N) sum_k x_k(t) exp(-i n theta_k),   n = 0 .. N-1,

so that x_k(t) = sum_n X_n(t) exp(i n theta_k): n is the nodal diameter (ND), the number of full
waves around the stage. With the time DFT as well, a component exp(i (n theta - w t)) of positive
frequency w is a wave travelling forward (in the direction of increasing theta) with n nodal
diameters, and exp(i (n theta + w t)) one travelling backward; for real x_k the backward wave of
n is the forward wave of N - n, mirrored. `travelling_waves` returns both, per ND and frequency.
"""
from __future__ import annotations

import re
from typing import Dict, List

import h5py
import numpy as np


def instances(path: str, body: str) -> List[str]:
    """The group names of `body`'s instances in a history file, in order: body[0], body[1], ..."""
    with h5py.File(path, "r") as f:
        names = [n for n in f["bodies"] if re.fullmatch(re.escape(body) + r"\[\d+\]", n)]
    if not names:
        raise KeyError(f"{path}: no instances of body '{body}' (groups bodies/{body}[k]); is it instanced?")
    return sorted(names, key=lambda n: int(n[len(body) + 1 : -1]))


def instance_histories(path: str, body: str, dataset: str) -> np.ndarray:
    """x[k, t, ...]: bodies/<body>[k]/<dataset> of every instance, stacked (e.g. dataset
    'nodesets/tip-le/displacement' gives x[k, t, node, 3])."""
    with h5py.File(path, "r") as f:
        return np.stack([f[f"bodies/{n}/{dataset}"][()] for n in instances(path, body)])


def nodal_diameters(x: np.ndarray) -> np.ndarray:
    """X[n, t, ...] = (1/N) sum_k x[k, t, ...] exp(-2 pi i n k / N): the spatial DFT over the instances
    (axis 0 of x), one nodal diameter n per row, n = 0 .. N-1."""
    return np.fft.fft(x, axis=0) / x.shape[0]


def nodal_diameter_content(x: np.ndarray) -> np.ndarray:
    """The RMS over time and components of each nodal diameter's X_n (n = 0 .. N-1)."""
    X = nodal_diameters(x)
    return np.sqrt(np.mean(np.abs(X.reshape(X.shape[0], -1)) ** 2, axis=1))


def travelling_waves(x: np.ndarray, dt: float) -> Dict[str, np.ndarray]:
    """The travelling-wave spectrum of x[k, t] (one scalar per instance and time; dt: the records' spacing).

    Returns frequency (Hz, >= 0), nd (0 .. N-1), forward[n, f] and backward[n, f]: the amplitudes of
    exp(i (n theta - w t)) and exp(i (n theta + w t)) components, from the 2D DFT over instances and
    time (a Hann window in time)."""
    N, T = x.shape[0], x.shape[1]
    w = np.hanning(T)
    S = np.fft.fft(np.fft.fft((x - x.mean(axis=1, keepdims=True)) * w, axis=1), axis=0) / (N * w.sum())
    nf = T // 2 + 1
    j = np.arange(nf)
    # x_k(t) = sum c exp(i (n theta_k + w t)): spatial index n, time frequency w. A wave
    # exp(i (n theta - w t)) with w > 0 sits at spatial index n and time index -j.
    forward, backward = np.abs(S[:, (-j) % T]), np.abs(S[:, j])
    return {
        "frequency": j / (T * dt),
        "nd": np.arange(N),
        "forward": 2 * forward,
        "backward": 2 * backward,
    }


def model_modes(rom_path: str, count: int = 20):
    """The lowest `count` modes of a reduced model's cache file (`<run>.<body>.rom.h5`): frequencies (Hz),
    the nodes' displacements u[mode, node, 3] = R phi, and the nodes' coordinates. Craig-Bampton or
    Guyan: the eigenpairs of (K, M); a massless boundary: its own modes (the body's normal modes with
    its clamps), phi = (Phi_b e_k, e_k): the retained DOFs follow the mode, its coordinate is 1."""
    with h5py.File(rom_path, "r") as f:
        K, M, R = f["K"][()], f["M"][()], f["recovery"][()]
        coords = f["coordinates"][()]
        method = f.attrs["method"]
        method = method.decode() if isinstance(method, bytes) else str(method)
        if method == "Massless boundary":
            nm, n = int(f.attrs["modes"]), int(f.attrs["size"])
            phib = f["boundaryModes"][()].reshape(nm, n - nm).T  # column-major, (n - nm) x nm
            count = min(count, nm)
            phi = np.vstack([phib[:, :count], np.eye(nm)[:, :count]])
            return f["modeFrequencies"][()][:count], (R @ phi).T.reshape(count, coords.shape[0], 3), coords
    if K.size == 0 or R.size == 0:
        raise ValueError(
            f"{rom_path}: no dense K and recovery (a lumped full model): reduce the body to read its modes"
        )
    L = np.linalg.cholesky(M)
    Li = np.linalg.inv(L)
    w2, V = np.linalg.eigh(Li @ K @ Li.T)
    phi = Li.T @ V[:, :count]
    u = (R @ phi).T.reshape(phi.shape[1], coords.shape[0], 3)
    return np.sqrt(np.maximum(w2[:count], 0.0)) / (2 * np.pi), u, coords


def _polar(coords: np.ndarray, axis=(0.0, 0.0, 1.0), center=(0.0, 0.0, 0.0)):
    """The nodes' angles about the axis (from the node farthest from it) and their unit radial vectors."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    r = coords - np.asarray(center, float)
    r = r - np.outer(r @ a, a)
    e1 = r[np.argmax(np.linalg.norm(r, axis=1))]
    e1 = e1 / np.linalg.norm(e1)
    theta = np.arctan2(r @ np.cross(a, e1), r @ e1)
    return theta, r / np.maximum(np.linalg.norm(r, axis=1), 1e-300)[:, None]


def nodal_diameter_of(u: np.ndarray, coords: np.ndarray, axis=(0.0, 0.0, 1.0), center=(0.0, 0.0, 0.0), nd_max=None):
    """The nodal diameter of a mode of a ring or casing (u[node, 3] its displacement at the nodes, coords
    their positions): the n whose circumferential harmonic holds most of the radial displacement,
    sum_nodes u_r exp(-i n theta) over the nodes' angles theta about the axis; and that share of the
    radial displacement's energy (1: a pure nodal-diameter mode)."""
    theta, er = _polar(coords, axis, center)
    ur = np.sum(u * er, axis=1)
    n_max = nd_max if nd_max is not None else max(1, len(np.unique(np.round(theta, 6))) // 2)
    power = np.array([abs(np.sum(ur * np.exp(-1j * n * theta))) ** 2 for n in range(n_max + 1)])
    n = int(np.argmax(power))
    return n, float(power[n] / max(power.sum(), 1e-300))


def interaction_speeds(blade_hz, casing_modes, nd_range=range(1, 1000)):
    """Legrand, Pierre, Cartraud & Lombard (JSV 319, 2009): the bladed disk and the casing exchange
    energy through contact when a wave of each with the same n nodal diameters turns at the same
    speed in the fixed frame: the casing's forward wave at omega_c / n and the bladed disk's backward
    wave (omega_b / n against its rotation, Omega - omega_b / n in the fixed frame), i.e. at

        Omega_n = (omega_b + omega_c,n) / n.

    With N blades the casing's wave of n diameters meets the blades at their N positions only, where
    it is a wave of n mod N diameters of the blades (a blade-assembly wave exp(i (p theta_k + w t))
    is the same at the blades for every p + j N): so every casing diameter n counts, not only
    n <= N / 2.

    blade_hz: the frequencies (Hz) of the bladed disk's modes of those diameters (on a rigid disk every
    diameter has the blade's own frequencies); casing_modes: [(frequency Hz, nodal diameter)]. Returns
    the rows (Omega_n rad/s, n, blade Hz, casing Hz), sorted by speed."""
    rows = []
    for fc, n in casing_modes:
        if n not in nd_range or n == 0:
            continue
        for fb in blade_hz:
            rows.append((2 * np.pi * (fb + fc) / n, n, fb, fc))
    return sorted(rows)


def ring_nodal_diameters(path: str, rom_path: str, body: str = "Casing", node_set: str = "inner", nd_max: int = 16):
    """The radial motion of a ring or casing's watched node set split into nodal diameters: times t and
    |X_n(t)| = |sum_nodes u_r exp(-i n theta)| / nodes for n = 0 .. nd_max (m), theta the nodes' angles
    about z (as nodal_diameter_of measures them). The nodes' positions come from the body's reduced-model cache file `rom_path`.
    """
    with h5py.File(rom_path, "r") as f:
        x = f["coordinates"][()][f[f"nodeSets/{node_set}"][()]]
    with h5py.File(path, "r") as f:
        u = f[f"bodies/{body}/nodesets/{node_set}/displacement"][()]  # [t, node, 3]
        t = f["time"][()]
    theta, er = _polar(x)
    ur = np.einsum("tnd,nd->tn", u, er)
    X = np.abs(ur @ np.exp(-1j * np.outer(theta, np.arange(nd_max + 1)))) / len(theta)
    return t, X.T
