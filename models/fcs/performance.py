"""The aircraft's performance as the flight management sees it: drag polar, airbrake, idle and
maximum thrust, and from them the gradients the vertical planner (:mod:`.vnav`) flies.

The database ``data/performance.json`` is *generated* from the models, never typed in:
``python -m openemss.models.performance.generate`` trims the UPERA airframe (JSBSim,
:func:`openemss.models.airframe.trim.trim_level`) at two masses on a grid of altitude and Mach
and fits the trimmed polar CD = CD0 + k CL^2 at each point, and runs the engine's steady states
(:class:`openemss.models.engine.offdesign.TurbofanOffDesign`) at a set of corrected fan speeds.
The FCS cannot import those packages (it is vendored into its own FMU), so it reads the tables.
When the aerodynamics or the engine change, regenerate the file
(``tests/fcs/test_performance.py`` fails until then).

Physics (flat Earth, point mass, steady, the thrust along the flight path):

    CL = n W cos(gamma) / (qbar S),   D = qbar S (CD0(h, M) + k(h, M) CL^2) + D_ab,
    D_ab = qbar S dCD_ab sin(p delta_max) / sin(delta_max),  capped at dCD_ab qbar_bb S (blow-back),

and the *energy gradient* -- the change of specific energy E = h + V^2/2g per distance flown,

    dE/ds = (T - D) / W,

which at constant true airspeed is sin(gamma) and in level flight V dV/ds / g. The planner
integrates it (:mod:`.vnav`).

References
----------
E. Torenbeek, "Advanced Aircraft Design", Wiley, 2013, ch. 11 (energy methods for climb and descent).
J. D. Anderson, "Aircraft Performance and Design", McGraw-Hill, 1999, ch. 5 (gliding flight,
rate of climb, energy height).
"""

from __future__ import annotations

import bisect
import json
import math
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources

import numpy as np

from ..common.airspeed import mach_from_tas
from ..infra.jit import jitable
from .atmosphere import G0_M_S2, isa
from .clip import clip
from .errors import FcsError
from .tunable import Tunable, load_params

__all__ = ["PerformanceData", "PerformanceParams", "Performance", "load_performance_data", "DATA_FILE",
           "airbrake_drag_law", "airbrake_position_law", "energy_rates_law"]

#: The generated database, in the package's data folder.
DATA_FILE = "performance.json"


def _interp(axis: tuple[float, ...], x: float) -> tuple[int, float]:
    """Index i and weight w with x ~ axis[i] (1 - w) + axis[i + 1] w, clamped to the axis."""
    if x <= axis[0]:
        return 0, 0.0
    if x >= axis[-1]:
        return len(axis) - 2, 1.0
    i = bisect.bisect_right(axis, x) - 1
    return i, (x - axis[i]) / (axis[i + 1] - axis[i])


def _bilinear(table: tuple[tuple[float, ...], ...], ia: int, wa: float, im: int, wm: float) -> float:
    r0, r1 = table[ia], table[ia + 1]
    return ((r0[im] * (1 - wm) + r0[im + 1] * wm) * (1 - wa) + (r1[im] * (1 - wm) + r1[im + 1] * wm) * wa)


@dataclass(frozen=True, slots=True)
class PerformanceData:
    """The tables of ``data/performance.json`` (see the file's ``_about`` for their source).

    Attributes
    ----------
    S_m2 : float
        Wing reference area [m^2].
    alt_m, mach : tuple of float
        Grid axes: geopotential altitude [m] and Mach [-].
    cd0, k : tuple of tuple of float
        Trimmed polar CD = cd0 + k CL^2 at [altitude][Mach] (clean, gear up) [-].
    cd_gear : float
        Drag increment of the landing gear [-].
    cd_airbrake : float
        Drag increment of the airbrake fully out [-].
    airbrake_max_rad : float
        Airbrake deflection fully out [rad] (drag ~ sin of the deflection).
    airbrake_blowback_qbar_Pa : float
        Above this dynamic pressure the airbrake's drag force is held at its value there [Pa].
    airbrake_rate_1_s : float
        Airbrake rate limit [1/s] (fraction of full travel per second).
    n1c_pct : tuple of float
        Corrected fan speeds of the thrust table [%].
    Fn_N : tuple of tuple of tuple of float
        Net thrust at [N1c][altitude][Mach] [N].
    thrust_max_N : tuple of tuple of float
        Maximum net thrust (lever 1: N1c 100 %, within the N1 and Tt41 limits) at [altitude][Mach] [N].
    source : str
        What generated the tables.
    """

    S_m2: float
    alt_m: tuple[float, ...]
    mach: tuple[float, ...]
    cd0: tuple[tuple[float, ...], ...]
    k: tuple[tuple[float, ...], ...]
    cd_gear: float
    cd_airbrake: float
    airbrake_max_rad: float
    airbrake_blowback_qbar_Pa: float
    airbrake_rate_1_s: float
    n1c_pct: tuple[float, ...]
    Fn_N: tuple[tuple[tuple[float, ...], ...], ...]
    thrust_max_N: tuple[tuple[float, ...], ...]
    source: str


def _tuple2(x: list) -> tuple[tuple[float, ...], ...]:
    return tuple(tuple(float(v) for v in row) for row in x)


def load_performance_data(text: str | None = None, where: str = DATA_FILE) -> PerformanceData:
    """Read the performance database (``text`` of a JSON file, default the shipped one).

    Raises
    ------
    FcsError
        If a table is missing or its shape does not match its axes.
    """
    if text is None:
        pkg = __package__ or __name__.rpartition(".")[0]
        text = resources.files(pkg).joinpath("data", DATA_FILE).read_text(encoding="utf-8")
    doc = json.loads(text)
    try:
        alt, mach, n1c = (tuple(float(v) for v in doc[k]) for k in ("alt_m", "mach", "n1c_pct"))
        ab = doc["airbrake"]
        data = PerformanceData(
            float(doc["S_m2"]), alt, mach, _tuple2(doc["cd0"]), _tuple2(doc["k"]), float(doc["cd_gear"]),
            float(ab["cd_full"]), math.radians(float(ab["max_deg"])), float(ab["blowback_qbar_Pa"]),
            1.0 / float(ab["full_travel_s"]), n1c, tuple(_tuple2(t) for t in doc["Fn_N"]),
            _tuple2(doc["thrust_max_N"]), str(doc.get("source", "")))
    except (KeyError, TypeError, ValueError) as e:
        raise FcsError(f"{where}: not a performance database ({type(e).__name__}: {e}); regenerate it with "
                       "python -m openemss.models.performance.generate") from None
    shapes = [("cd0", data.cd0, (len(alt), len(mach))), ("k", data.k, (len(alt), len(mach))),
              ("thrust_max_N", data.thrust_max_N, (len(alt), len(mach)))]
    shapes += [(f"Fn_N[{i}]", t, (len(alt), len(mach))) for i, t in enumerate(data.Fn_N)]
    for name, t, (na, nm) in shapes:
        if len(t) != na or any(len(r) != nm for r in t):
            raise FcsError(f"{where}: table {name} is not {na} x {nm} (altitude x Mach)")
    if len(data.Fn_N) != len(n1c):
        raise FcsError(f"{where}: Fn_N has {len(data.Fn_N)} N1c levels for {len(n1c)} in n1c_pct")
    return data


@dataclass(frozen=True, slots=True)
class PerformanceParams:
    """Calibration of the planner's performance model (data/vnav.yaml, section ``performance``)."""

    drag_factor: float
    airbrake_factor: float
    idle_thrust_delta_N: float

    @classmethod
    def from_file(cls, **overrides: float) -> PerformanceParams:
        """Parameter set of ``data/vnav.yaml``, section ``performance``."""
        return load_params(cls, "vnav.yaml", "performance", **overrides)


class Performance(Tunable[PerformanceParams]):
    """Drag, thrust and gradients of the aircraft from the generated database.

    Parameters
    ----------
    data : PerformanceData, optional
        The tables (default: the shipped ``data/performance.json``).
    params : PerformanceParams, optional
        Calibration factors (default: ``data/vnav.yaml``).
    n1c_idle : callable, optional
        Returns the flight idle's corrected fan speed [%] (the fuel controller's ``N1c_idle_pct``, which
        is defined there once); default 0, the lowest fan speed of the table.
    """

    tunable_name = "performance"

    def __init__(self, data: PerformanceData | None = None, params: PerformanceParams | None = None,
                 n1c_idle: Callable[[], float] | None = None) -> None:
        self.data = data if data is not None else _shipped()
        self._params = params if params is not None else PerformanceParams.from_file()
        self._n1c_idle = n1c_idle if n1c_idle is not None else (lambda: 0.0)

    # -- drag ----------------------------------------------------------------------------
    def polar(self, alt_m: float, mach: float) -> tuple[float, float]:
        """(CD0, k) of the trimmed clean polar at altitude [m] and Mach [-], times ``drag_factor``."""
        d = self.data
        ia, wa = _interp(d.alt_m, alt_m)
        im, wm = _interp(d.mach, mach)
        f = self._params.drag_factor
        return f * _bilinear(d.cd0, ia, wa, im, wm), f * _bilinear(d.k, ia, wa, im, wm)

    def airbrake_full_N_Pa(self) -> float:
        """Drag of the fully extended airbrake per dynamic pressure, before its blow-back [N/Pa]."""
        d = self.data
        return d.cd_airbrake * self._params.airbrake_factor * d.S_m2

    def airbrake_drag_N(self, qbar_Pa: float, position: float = 1.0) -> float:
        """Drag of the airbrake at ``position`` [0, 1] and dynamic pressure [Pa], blow-back included [N]."""
        d = self.data
        return airbrake_drag_law(self.airbrake_full_N_Pa(), d.airbrake_max_rad, d.airbrake_blowback_qbar_Pa, qbar_Pa,
                                 position)

    def airbrake_position(self, drag_N: float, qbar_Pa: float) -> float:
        """Airbrake position [0, 1] that gives ``drag_N`` [N] at ``qbar_Pa`` [Pa] (1 if it cannot)."""
        return airbrake_position_law(self.airbrake_full_N_Pa(), self.data.airbrake_max_rad, drag_N, qbar_Pa)

    def airbrake_values(self) -> np.ndarray:
        """(S [m^2], CD of the gear [-], :meth:`airbrake_full_N_Pa`, airbrake's deflection at full extension [rad],
        blow-back dynamic pressure [Pa]): the constants of :func:`energy_rates_law` and
        :func:`airbrake_position_law`, for the FCS's compiled step."""
        d = self.data
        return np.array([d.S_m2, d.cd_gear, self.airbrake_full_N_Pa(), d.airbrake_max_rad, d.airbrake_blowback_qbar_Pa])

    def drag_N(self, alt_m: float, tas_m_s: float, mass_kg: float, airbrake: float = 0.0, gear: bool = False,
               load_factor: float = 1.0, gamma_rad: float = 0.0, dT_isa_K: float = 0.0) -> float:
        """Drag [N] in steady flight at altitude [m], true airspeed [m/s], mass [kg], airbrake position [0, 1],
        gear, load factor [-] (1/cos(bank) in a level turn) and flight-path angle [rad]."""
        atm = isa(alt_m, dT_isa_K)
        q = 0.5 * atm.rho_kg_m3 * tas_m_s * tas_m_s
        cd0, k = self.polar(alt_m, tas_m_s / atm.a_m_s)
        cl = load_factor * mass_kg * G0_M_S2 * math.cos(gamma_rad) / (q * self.data.S_m2)
        cd = cd0 + k * cl * cl + (self.data.cd_gear if gear else 0.0)
        return q * self.data.S_m2 * cd + self.airbrake_drag_N(q, airbrake)

    # -- thrust --------------------------------------------------------------------------
    def Fn_N(self, alt_m: float, mach: float, n1c_pct: float) -> float:
        """Net thrust at a corrected fan speed [%] (held at the table's ends) [N]."""
        d = self.data
        ia, wa = _interp(d.alt_m, alt_m)
        im, wm = _interp(d.mach, mach)
        jn, wn = _interp(d.n1c_pct, n1c_pct)
        t0 = _bilinear(d.Fn_N[jn], ia, wa, im, wm)
        t1 = _bilinear(d.Fn_N[jn + 1], ia, wa, im, wm)
        return t0 * (1 - wn) + t1 * wn

    def idle_thrust_N(self, alt_m: float, mach: float) -> float:
        """Net thrust at flight idle (``N1c_idle_pct``; at the table's lowest N1c when that is below it) [N]."""
        return self.Fn_N(alt_m, mach, self._n1c_idle()) + self._params.idle_thrust_delta_N

    def max_thrust_N(self, alt_m: float, mach: float) -> float:
        """Maximum net thrust (lever 1, within the engine's N1 and Tt41 limits) [N]."""
        d = self.data
        ia, wa = _interp(d.alt_m, alt_m)
        im, wm = _interp(d.mach, mach)
        return _bilinear(d.thrust_max_N, ia, wa, im, wm)

    # -- gradients -----------------------------------------------------------------------
    def energy_gradient(self, alt_m: float, tas_m_s: float, mass_kg: float, thrust: str = "idle",
                        airbrake: float = 0.0, gear: bool = False, load_factor: float = 1.0,
                        dT_isa_K: float = 0.0) -> float:
        """(T - D) / W: the specific energy gained per distance flown [-] (< 0 losing energy).

        ``thrust`` is ``"idle"`` or ``"max"``. For a steady descent or climb at constant true airspeed it
        is sin(gamma); the drag is taken at the lift of level flight (cos(gamma) ~ 1: 0.6 % at 6 deg).
        """
        atm = isa(alt_m, dT_isa_K)
        mach = tas_m_s / atm.a_m_s
        t = self.idle_thrust_N(alt_m, mach) if thrust == "idle" else self.max_thrust_N(alt_m, mach)
        d = self.drag_N(alt_m, tas_m_s, mass_kg, airbrake, gear, load_factor, dT_isa_K=dT_isa_K)
        return (t - d) / (mass_kg * G0_M_S2)

    def lookup(self, alt_m: float, mach: float) -> tuple[float, float, float, float]:
        """(CD0, k, idle thrust [N], maximum thrust [N]) at altitude [m] and Mach [-]: the table look-ups of
        :meth:`energy_rates`, which a caller may keep for a while (they change slowly)."""
        return (*self.polar(alt_m, mach), self.idle_thrust_N(alt_m, mach), self.max_thrust_N(alt_m, mach))

    def energy_rates(self, lookup: tuple[float, float, float, float], qbar_Pa: float, mass_kg: float,
                     bank_rad: float = 0.0, gear: bool = False, airbrake: bool = False) -> tuple[float, float, float]:
        """(E_rate_min, E_rate_max, airbrake drag [N]): (T - D)/W at idle, less the airbrake fully out when
        ``airbrake``, and at maximum thrust [-], with the drag of the lift of a level turn at ``bank_rad``
        (load factor 1/cos, at most 3.3) at ``qbar_Pa`` [Pa]; ``lookup`` from :meth:`lookup`. These bound the
        energy rate the thrust can give, the limits of TECS's commands (:mod:`.tecs`)."""
        d = self.data
        return energy_rates_law(*lookup, d.S_m2, d.cd_gear, self.airbrake_full_N_Pa(), d.airbrake_max_rad,
                                d.airbrake_blowback_qbar_Pa, qbar_Pa, mass_kg, bank_rad, gear, airbrake)

    def mach(self, alt_m: float, tas_m_s: float, dT_isa_K: float = 0.0) -> float:
        """Mach number of a true airspeed at altitude [-]."""
        return mach_from_tas(tas_m_s, isa(alt_m, dT_isa_K))


@jitable
def airbrake_drag_law(full_N_Pa: float, max_rad: float, blowback_qbar_Pa: float, qbar_Pa: float,
                      position: float) -> float:
    """:meth:`Performance.airbrake_drag_N` on plain values: the full airbrake's drag per dynamic pressure [N/Pa],
    its deflection at full extension [rad] and blow-back dynamic pressure [Pa], then the arguments [N]."""
    p = clip(position, 0.0, 1.0)
    # min written out (the builtin costs ~0.1 us a call, and the FCS asks at every step of a descent)
    drag = full_N_Pa * qbar_Pa * math.sin(p * max_rad) / math.sin(max_rad)
    blown = full_N_Pa * blowback_qbar_Pa
    return blown if blown < drag else drag


@jitable
def airbrake_position_law(full_N_Pa: float, max_rad: float, drag_N: float, qbar_Pa: float) -> float:
    """:meth:`Performance.airbrake_position` on plain values (the first two as :func:`airbrake_drag_law`'s) [-]."""
    full = full_N_Pa * (1.0 if 1.0 > qbar_Pa else qbar_Pa)
    if drag_N <= 0.0:
        return 0.0
    x = drag_N / full * math.sin(max_rad)
    return 1.0 if x >= math.sin(max_rad) else math.asin(x) / max_rad


@jitable
def energy_rates_law(cd0: float, k: float, t_idle_N: float, t_max_N: float, S_m2: float, cd_gear: float,
                     full_N_Pa: float, max_rad: float, blowback_qbar_Pa: float, qbar_Pa: float, mass_kg: float,
                     bank_rad: float, gear: bool, airbrake: bool) -> tuple[float, float, float]:
    """:meth:`Performance.energy_rates` on plain values: the look-up's four values, the wing area [m^2], the gear's
    CD [-], the airbrake's constants (as :func:`airbrake_drag_law`'s), then the arguments."""
    # max(qbar, 1) and max(cos(bank), 0.3) written out (the builtins cost ~0.1 us a call; the same values)
    q, S = (1.0 if 1.0 > qbar_Pa else qbar_Pa), S_m2
    W = mass_kg * G0_M_S2
    c = math.cos(bank_rad)
    cl = W / (q * S * (0.3 if 0.3 > c else c))
    drag = q * S * (cd0 + k * cl * cl + (cd_gear if gear else 0.0))
    ab = airbrake_drag_law(full_N_Pa, max_rad, blowback_qbar_Pa, q, 1.0) if airbrake else 0.0
    return (t_idle_N - drag - ab) / W, (t_max_N - drag) / W, ab


_SHIPPED: list[PerformanceData] = []


def _shipped() -> PerformanceData:
    if not _SHIPPED:
        _SHIPPED.append(load_performance_data())
    return _SHIPPED[0]
