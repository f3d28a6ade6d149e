"""A vortex-lattice method for flat trapezoidal wings: an independent check of the handbook lift slope,
span efficiency and Prandtl-Glauert scaling used in :mod:`.aero`.

Horseshoe vortices, with the bound leg at the quarter-chord of each panel and the
control point at the three-quarter chord, and trailing legs to +infinity along x.
Compressibility enters by the Göthert (Prandtl-Glauert) transformation: x is stretched
by 1/beta, the incompressible problem is solved, and CL is divided by beta. Induced drag
comes from the Trefftz plane.

References
----------
.. [1] Katz, J., Plotkin, A., *Low-Speed Aerodynamics*, 2nd ed., Cambridge, 2001,
   sect. 12.1 (horseshoe lattice) and 10.4.4 (Biot-Savart segment).
.. [2] Bertin, J. J., Cummings, R. M., *Aerodynamics for Engineers*, 6th ed., Pearson,
   2014, sect. 7.4 (VLM) and 9.4 (Göthert rule).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .geometry import Planform

__all__ = ["VlmResult", "vlm_wing", "vlm_downwash_gradient"]


@dataclass(frozen=True)
class VlmResult:
    """Lift-curve slope [1/rad], span efficiency e = CL^2/(pi A CDi) [-], and the span load."""

    cl_alpha: float
    span_efficiency: float
    y_m: NDArray
    gamma_norm: NDArray  # circulation / (V alpha), per strip [m]


def _segment(p: NDArray, a: NDArray, b: NDArray) -> NDArray:
    """Velocity at points p (n,3) induced by unit-strength segments a->b (m,3): array (n, m, 3)."""
    r1 = p[:, None, :] - a[None, :, :]
    r2 = p[:, None, :] - b[None, :, :]
    cross = np.cross(r1, r2)
    c2 = np.einsum("ijk,ijk->ij", cross, cross)
    n1 = np.linalg.norm(r1, axis=2)
    n2 = np.linalg.norm(r2, axis=2)
    r0 = (b - a)[None, :, :]
    dot = np.einsum("ijk,ijk->ij", r0, r1 / n1[..., None] - r2 / n2[..., None])
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(c2 > 1e-12, dot / (4 * math.pi * c2), 0.0)
    return cross * k[..., None]


def _semi_infinite(p: NDArray, a: NDArray) -> NDArray:
    """Velocity at p induced by unit-strength semi-infinite lines from a along +x (n, m, 3)."""
    r = p[:, None, :] - a[None, :, :]
    ry, rz = r[..., 1], r[..., 2]
    d2 = ry ** 2 + rz ** 2
    n = np.linalg.norm(r, axis=2)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(d2 > 1e-12, (1 + r[..., 0] / n) / (4 * math.pi * d2), 0.0)
    # direction (1,0,0) x r = (0, -rz, ry)
    return np.stack([np.zeros_like(ry), -rz * f, ry * f], axis=-1)


def _solve(p: Planform, mach: float, n_span: int, n_chord: int) -> tuple[NDArray, ...]:
    """Lattice and circulations for V alpha = 1 on the planform stretched by 1/beta."""
    beta = math.sqrt(1.0 - mach ** 2)
    s = p.semi_span_m
    # uniform spanwise stations (cosine spacing with mid-panel control points converges worse here)
    y_edges = -s + 2 * s * np.linspace(0.0, 1.0, n_span + 1)
    x_le = np.abs(y_edges) * p.tan_sweep(0.0)
    c = np.array([p.chord_m(abs(y)) for y in y_edges])
    frac = np.linspace(0.0, 1.0, n_chord + 1)
    xs = (x_le[None, :] + frac[:, None] * c[None, :]) / beta  # corner x, stretched (Göthert)
    x_qc = xs[:-1] + 0.25 * (xs[1:] - xs[:-1])  # (n_chord, n_span+1): bound legs at panel quarter chords
    x_tq = xs[:-1] + 0.75 * (xs[1:] - xs[:-1])
    a = np.stack([x_qc[:, :-1], np.broadcast_to(y_edges[:-1], x_qc[:, :-1].shape), np.zeros_like(x_qc[:, :-1])],
                 axis=-1).reshape(-1, 3)
    b = np.stack([x_qc[:, 1:], np.broadcast_to(y_edges[1:], x_qc[:, 1:].shape), np.zeros_like(x_qc[:, 1:])],
                 axis=-1).reshape(-1, 3)
    y_mid = 0.5 * (y_edges[:-1] + y_edges[1:])
    ctrl = np.stack([0.5 * (x_tq[:, :-1] + x_tq[:, 1:]), np.broadcast_to(y_mid, x_tq[:, 1:].shape),
                     np.zeros_like(x_tq[:, 1:])], axis=-1).reshape(-1, 3)
    gamma = np.linalg.solve(_horseshoe_w(ctrl, a, b), -np.ones(len(ctrl)))  # induced w = -V alpha
    return a, b, gamma, y_edges, beta


def _horseshoe_w(points: NDArray, a: NDArray, b: NDArray) -> NDArray:
    """Vertical velocity at ``points`` per unit circulation of each horseshoe (n_points, n_vortices)."""
    return _segment(points, a, b)[..., 2] + _semi_infinite(points, b)[..., 2] - _semi_infinite(points, a)[..., 2]


def vlm_wing(p: Planform, mach: float = 0.0, n_span: int = 160, n_chord: int = 4) -> VlmResult:
    """Vortex-lattice solution of the flat planform ``p`` (both halves) at Mach ``mach``."""
    a, b, gamma, y_edges, _ = _solve(p, mach, n_span, n_chord)
    dy = np.diff(y_edges)
    g_strip = gamma.reshape(n_chord, n_span).sum(axis=0)
    # CL of the real wing = CL of the stretched wing (area S/beta) / beta = 2 sum(G dy) / (V alpha S)
    cl_alpha = 2.0 * np.sum(g_strip * dy) / p.area_m2
    # Trefftz plane: trailing lines at the strip edges carry the jumps of the strip circulation
    y_mid = 0.5 * (y_edges[:-1] + y_edges[1:])
    shed = np.diff(np.concatenate([[0.0], g_strip, [0.0]]))
    w_tp = np.sum(shed[None, :] / (2 * math.pi * (y_mid[:, None] - y_edges[None, :])), axis=1)
    cdi = np.sum(g_strip * w_tp * dy) / p.area_m2  # per (V alpha)^2
    e = cl_alpha ** 2 / (math.pi * p.aspect_ratio * cdi)
    return VlmResult(cl_alpha=float(cl_alpha), span_efficiency=float(e), y_m=y_mid, gamma_norm=g_strip)


def vlm_downwash_gradient(p: Planform, x_m: float, z_m: float, half_span_m: float, mach: float = 0.0,
                          n_span: int = 160, n_chord: int = 4, n_points: int = 21) -> float:
    """Mean d(epsilon)/d(alpha) behind the wing at ``x_m`` aft of the root leading edge and ``z_m``
    above the wing plane, averaged over |y| < ``half_span_m`` (a tail's semi-span) [-]."""
    a, b, gamma, _, beta = _solve(p, mach, n_span, n_chord)
    ys = np.linspace(-half_span_m, half_span_m, n_points)
    pts = np.stack([np.full_like(ys, x_m / beta), ys, np.full_like(ys, z_m)], axis=-1)
    w = _horseshoe_w(pts, a, b) @ gamma  # per V alpha; downwash = -w
    return float(-np.mean(w))
