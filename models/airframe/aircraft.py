"""Any JSBSim aircraft, flown on engines computed outside JSBSim: what the adapter needs of its file.

The convention (created on load, nothing of the aircraft's files is changed):

* **Which aircraft.** ``aircraft`` is a folder of the user's holding a JSBSim aircraft file (``<folder
  name>.xml``, or the folder's one XML file whose root is ``fdm_config``), or the name of an aircraft of
  this package (``jsbsim/aircraft/``: UPERA) or of the ``jsbsim`` package's own set (``c172x``, ``737``,
  ``A320``, ``T37``, ``T38``...).
* **Engines become thrust forces.** Every ``propulsion/engine`` of the file is removed (no thrust from
  JSBSim's engine models, no fuel burned by them), and an external force along its thruster's axis is
  put at its thruster's location (the engine's when the thruster gives none): ``external_reactions/thrust``
  for the first engine, ``thrust_2``, ``thrust_3``... for the others, in the file's order. The axis is the
  body x axis turned by the thruster's ``orient`` pitch and yaw (JSBSim's thruster convention). An
  aircraft without an engine is refused.
* **Properties of the removed engines** that the aircraft's own systems read (a throttle command, a
  propulsive force...) are declared 0, found by loading the aircraft and flying it a few frames.
* **Tanks, mass, CG and inertia** are the file's. The fuel on board is spread over the fuel tanks in
  proportion to their capacities (they empty together); the fuel the engines report burning is taken
  from them so. A point mass ``openEMSS payload`` at the empty CG carries the payload and any mass added
  at run time.
* **Values JSBSim's format has no place for**: an optional ``openemss.json`` beside the aircraft file
  (``mtom_kg``: the maximum take-off mass; ``rest_cg_height_m``: the CG's height above the runway at rest,
  where the aircraft is put before its gear settles). Without it there is no maximum take-off mass, and
  the rest height is the CG's height above the lowest wheel less half the gear's static deflection
  under the aircraft's weight (all wheels alike).

The modified file is written to a temporary folder of the process (removed at exit), beside links to the
aircraft's other files, so JSBSim finds its systems and tables where they were. JSBSim has no API to add
an external force or remove an engine after loading (``FGFDMExec`` in jsbsim 1.3), hence the rewritten
file.

References
----------
.. [1] Berndt, J. S., and the JSBSim team, *JSBSim Reference Manual*: the aircraft configuration file
   (``mass_balance``, ``propulsion``, ``external_reactions``, ``ground_reactions``),
   https://jsbsim-team.github.io/jsbsim-reference-manual/
"""
from __future__ import annotations

import atexit
import contextlib
import ctypes
import hashlib
import json
import math
import os
import re
import shutil
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from .errors import AirframeError

__all__ = ["Aircraft", "Thruster", "Tank", "load_aircraft", "resolve_aircraft", "thrust_force", "DEFAULT_AIRCRAFT",
           "MAX_ENGINES", "OWN_ROOT", "PAYLOAD_POINTMASS", "COMMAND_PROPERTIES"]

#: This package's JSBSim root (its aircraft: UPERA).
OWN_ROOT = Path(__file__).resolve().parent / "jsbsim"
DEFAULT_AIRCRAFT = "UPERA"
#: Engines an aircraft may have: the airframe FMU's thrust and fuel-flow inputs (Fn_N, Fn_N_2... Fn_N_4).
MAX_ENGINES = 4
PAYLOAD_POINTMASS = "openEMSS payload"
SIDECAR = "openemss.json"
#: The commands the adapter writes each step (made where the aircraft has none): JSBSim's standard names.
COMMAND_PROPERTIES = tuple(f"fcs/{p}-cmd-norm" for p in ("aileron", "elevator", "rudder", "flap", "airbrake",
                                                         "left-brake", "right-brake", "steer"))
G0 = 9.80665  # [m/s^2] standard gravity

# JSBSim's units of the elements read here -> SI factor (JSBSim's defaults: IN, LBS, SLUG*FT2, LBS/FT)
_FT = 0.3048
_LB = 0.45359237
_SLUG = 14.593902937206364
_UNITS = {"IN": _FT / 12.0, "FT": _FT, "M": 1.0, "CM": 0.01, "KM": 1000.0,
          "LBS": _LB, "KG": 1.0, "SLUG": _SLUG,
          "SLUG*FT2": _SLUG * _FT ** 2, "KG*M2": 1.0,
          "LBS/FT": 4.4482216152605 / _FT, "N/M": 1.0, "DEG": math.pi / 180.0, "RAD": 1.0}
_MISSING = re.compile(r"property (\S+) does not exist")
_DISCOVERY_ROUNDS = 60  # properties of removed engines declared at most (one per load)


@dataclass(frozen=True)
class Thruster:
    """Where an engine's thrust acts: ``force`` (the external force's name), location in JSBSim's structural
    frame (x aft, y right, z up) [m] and unit direction in body axes (x forward, y right, z down) [-]."""

    force: str
    location_m: tuple[float, float, float]
    direction: tuple[float, float, float]


@dataclass(frozen=True)
class Tank:
    """A fuel tank: location (structural frame) [m], capacity and the file's contents [kg]."""

    location_m: tuple[float, float, float]
    capacity_kg: float
    contents_kg: float


@dataclass(frozen=True)
class Aircraft:
    """A JSBSim aircraft as the adapter flies it (see the module for the convention).

    Attributes
    ----------
    name : the aircraft's name (its file's stem)
    source : the aircraft's own file
    root : JSBSim root of the prepared copy (``root/aircraft/<name>/<name>.xml``), with ``engine_path``
        and ``systems_path`` for JSBSim's search
    empty_mass_kg : the file's empty weight [kg]
    cg_m : the empty CG in the structural frame [m]
    inertia_kg_m2 : Ixx, Iyy, Izz of the empty aircraft [kg m^2]
    tanks, thrusters : the fuel tanks and the engines' thrust forces, in the file's order
    wingspan_m : span [m]
    rest_cg_height_m : the CG's height above the runway where a runway start puts it [m]
    cg_height_on_wheels_m : the CG's height above the lowest wheel, gear uncompressed [m]
    mtom_kg : maximum take-off mass [kg] or None (``openemss.json``)
    fuel_tank_indices : JSBSim's index of each fuel tank (``propulsion/tank[i]``)
    payload_index : JSBSim's index of the payload point mass (``inertia/pointmass-weight-lbs[i]``)
    """

    name: str
    source: Path
    root: Path
    engine_path: Path
    systems_path: Path
    empty_mass_kg: float
    cg_m: tuple[float, float, float]
    inertia_kg_m2: tuple[float, float, float]
    tanks: tuple[Tank, ...]
    thrusters: tuple[Thruster, ...]
    wingspan_m: float
    rest_cg_height_m: float
    cg_height_on_wheels_m: float
    mtom_kg: float | None
    fuel_tank_indices: tuple[int, ...]
    payload_index: int

    @property
    def fuel_capacity_kg(self) -> float:
        """Capacity of all fuel tanks [kg]."""
        return sum(t.capacity_kg for t in self.tanks)

    @property
    def fuel_shares(self) -> tuple[float, ...]:
        """Each tank's share of the fuel on board (its capacity over the total) [-]."""
        cap = self.fuel_capacity_kg
        return tuple(t.capacity_kg / cap for t in self.tanks)


def thrust_force(i: int) -> str:
    """The external force of engine ``i`` (0-based): ``thrust``, ``thrust_2``..."""
    return "thrust" if i == 0 else f"thrust_{i + 1}"


def _stock_root() -> Path | None:
    try:
        import jsbsim  # the model package loads without JSBSim for table work

        return Path(jsbsim.get_default_root_dir())
    # jsbsim missing, or installed without its data (its get_default_root_dir raises OSError): no stock aircraft
    except (ImportError, AttributeError, OSError):  # pragma: no cover
        return None


def _fdm_file(folder: Path) -> Path | None:
    own = folder / f"{folder.name}.xml"
    if own.is_file():
        return own
    found = [p for p in sorted(folder.glob("*.xml")) if _is_fdm(p)]
    return found[0] if len(found) == 1 else None


def _is_fdm(p: Path) -> bool:
    try:
        return ET.parse(p).getroot().tag == "fdm_config"
    except (ET.ParseError, OSError):
        return False


def resolve_aircraft(aircraft: str, base: Path | None = None) -> Path:
    """The JSBSim file of ``aircraft``: a folder (absolute, or relative to the working directory or to
    ``base``), or a name of this package's or the jsbsim package's aircraft. Raises :class:`AirframeError`
    (one line) for anything else."""
    a = str(aircraft).strip()
    if not a:
        raise AirframeError("aircraft: empty; give a JSBSim aircraft's name (e.g. UPERA, 737, T38) or a folder "
                            "holding its XML file")
    looks_like_path = os.sep in a or "/" in a or a.startswith(".")
    candidates = [Path(a)] + ([base / a] if base is not None and not Path(a).is_absolute() else [])
    for folder in candidates:
        if folder.is_dir():
            f = _fdm_file(folder)
            if f is None:
                raise AirframeError(f"aircraft: folder {folder} holds no JSBSim aircraft file (allowed: "
                                    f"{folder.name}.xml, or one XML file whose root element is fdm_config)")
            return f.resolve()
    if looks_like_path:
        raise AirframeError(f"aircraft: folder '{a}' not found (give an absolute path, or a name of JSBSim's "
                            "aircraft such as 737 or T38)")
    if (OWN_ROOT / "aircraft" / a / f"{a}.xml").is_file():  # our own first: no need of the jsbsim package's data
        return (OWN_ROOT / "aircraft" / a / f"{a}.xml").resolve()
    stock = _stock_root()
    if stock is not None and (stock / "aircraft" / a / f"{a}.xml").is_file():
        return (stock / "aircraft" / a / f"{a}.xml").resolve()
    names = sorted(p.name for p in (stock / "aircraft").iterdir() if p.is_dir()) if stock is not None else []
    raise AirframeError(f"aircraft: '{a}' is neither a folder nor a known aircraft (allowed: {DEFAULT_AIRCRAFT}, "
                        f"a folder, or one of the jsbsim package's: {', '.join(names[:12])}...)")


# -- reading the file ---------------------------------------------------------------------------------
def _num(el: ET.Element | None, what: str, src: Path, unit: str, default: float | None = None) -> float:
    if el is None or el.text is None or not el.text.strip():
        if default is not None:
            return default
        raise AirframeError(f"aircraft: {src}: {what} missing (a JSBSim aircraft file gives it)")
    u = (el.get("unit") or unit).upper()
    if u not in _UNITS:
        raise AirframeError(f"aircraft: {src}: {what} in unit '{u}', which is not read here (allowed: "
                            f"{', '.join(_UNITS)})")
    try:
        return float(el.text) * _UNITS[u]
    except ValueError:
        raise AirframeError(f"aircraft: {src}: {what} = '{el.text.strip()}' is not a number") from None


def _xyz(el: ET.Element | None, what: str, src: Path, unit: str) -> tuple[float, float, float]:
    if el is None:
        raise AirframeError(f"aircraft: {src}: {what} missing")
    u = el.get("unit") or unit
    out = []
    for c in "xyz":
        sub = el.find(c)
        if sub is not None and sub.get("unit") is None:
            sub = _with_unit(sub, u)
        out.append(_num(sub, f"{what} {c}", src, u, 0.0))
    return out[0], out[1], out[2]


def _with_unit(el: ET.Element, unit: str) -> ET.Element:
    e = ET.Element(el.tag, {"unit": unit})
    e.text = el.text
    return e


def _inline(root: ET.Element, tag: str, folder: Path, src: Path) -> ET.Element | None:
    """The section ``tag``, with a ``file`` attribute's content put in its place (JSBSim's section files)."""
    el = root.find(tag)
    if el is None or el.get("file") is None:
        return el
    name = el.get("file", "")
    p = next((q for q in (folder / name, folder / f"{name}.xml") if q.is_file()), None)
    if p is None:
        raise AirframeError(f"aircraft: {src}: the {tag} section's file '{name}' not found in {folder}")
    try:
        sub = ET.parse(p).getroot()
    except ET.ParseError as exc:
        raise AirframeError(f"aircraft: {p}: not valid XML ({exc})") from None
    i = list(root).index(el)
    root.remove(el)
    root.insert(i, sub)
    return sub


def _thruster(i: int, engine: ET.Element, src: Path) -> Thruster:
    th = engine.find("thruster")
    where = th if th is not None and th.find("location") is not None else engine
    loc = _xyz(where.find("location"), f"engine {i + 1}'s thruster location", src, "IN")
    o = where.find("orient")
    pitch = yaw = 0.0
    if o is not None:
        u = o.get("unit") or "DEG"
        pitch = _num(_with_unit(o.find("pitch"), u) if o.find("pitch") is not None else None, "", src, u, 0.0)
        yaw = _num(_with_unit(o.find("yaw"), u) if o.find("yaw") is not None else None, "", src, u, 0.0)
    cp, sp, cy, sy = math.cos(pitch), math.sin(pitch), math.cos(yaw), math.sin(yaw)
    return Thruster(thrust_force(i), loc, (cp * cy, cp * sy, -sp))


def _rest_height(contacts: list[tuple[float, float]], cg_z_m: float, mass_kg: float) -> tuple[float, float]:
    """(rest height, height on uncompressed wheels) of the CG [m] from the wheels' (z [m], spring [N/m])."""
    z_low = min(z for z, _ in contacts)
    on_wheels = cg_z_m - z_low
    k = sum(s for _, s in contacts)
    return on_wheels - 0.5 * mass_kg * G0 / k, on_wheels


def _sidecar(folder: Path) -> dict[str, float]:
    p = folder / SIDECAR
    if not p.is_file():
        return {}
    try:
        d = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise AirframeError(f"aircraft: {p}: not valid JSON ({exc})") from None
    allowed = ("mtom_kg", "rest_cg_height_m")
    out = {}
    for k, v in d.items():
        if k in ("source", "note"):
            continue
        if k not in allowed or not isinstance(v, (int, float)) or isinstance(v, bool) or not v > 0.0:
            raise AirframeError(f"aircraft: {p}: '{k}': {v!r} is not allowed (allowed: {', '.join(allowed)}, "
                                "positive numbers; source, note: text)")
        out[k] = float(v)
    return out


# -- preparing the copy --------------------------------------------------------------------------------
_PREPARED: dict[tuple[str, str], Aircraft] = {}
_TMP: list[Path] = []


def _tmp_root() -> Path:
    if not _TMP:
        _TMP.append(Path(tempfile.mkdtemp(prefix="openemss-aircraft-")))
        atexit.register(shutil.rmtree, _TMP[0], True)
    return _TMP[0]


def load_aircraft(aircraft: str = DEFAULT_AIRCRAFT, base: Path | None = None) -> Aircraft:
    """The aircraft ``aircraft`` (see :func:`resolve_aircraft`), prepared for JSBSim as the module says
    (once per process and file content). Raises :class:`AirframeError` with one line for a file that is
    not a flyable aircraft (no engine, more than :data:`MAX_ENGINES`, no fuel tank, no wheel)."""
    src = resolve_aircraft(aircraft, base)
    data = src.read_bytes()
    key = (str(src), hashlib.sha256(data).hexdigest())
    if key in _PREPARED:
        return _PREPARED[key]
    try:
        tree = ET.ElementTree(ET.fromstring(data))
    except ET.ParseError as exc:
        raise AirframeError(f"aircraft: {src}: not valid XML ({exc})") from None
    root = tree.getroot()
    if root.tag != "fdm_config":
        raise AirframeError(f"aircraft: {src}: root element <{root.tag}>, not a JSBSim aircraft (<fdm_config>)")
    folder = src.parent
    mb = _inline(root, "mass_balance", folder, src)
    prop = _inline(root, "propulsion", folder, src)
    gr = _inline(root, "ground_reactions", folder, src)
    metrics = _inline(root, "metrics", folder, src)
    if mb is None or metrics is None:
        raise AirframeError(f"aircraft: {src}: no {'mass_balance' if mb is None else 'metrics'} section")
    engines = prop.findall("engine") if prop is not None else []
    if not engines:
        raise AirframeError(f"aircraft: {src}: no engine (propulsion/engine): the convention puts our engines' "
                            "thrust where the aircraft's engines are; give the file an engine with its thruster")
    if len(engines) > MAX_ENGINES:
        raise AirframeError(f"aircraft: {src}: {len(engines)} engines, more than the airframe's {MAX_ENGINES} "
                            "thrust inputs (Fn_N, Fn_N_2...)")
    thrusters = tuple(_thruster(i, e, src) for i, e in enumerate(engines))
    all_tanks = prop.findall("tank")  # type: ignore[union-attr]
    fuel_idx = tuple(i for i, t in enumerate(all_tanks) if (t.get("type") or "FUEL").upper() == "FUEL")
    tanks = tuple(Tank(_xyz(all_tanks[i].find("location"), "tank location", src, "IN"),
                       _num(all_tanks[i].find("capacity"), "tank capacity", src, "LBS"),
                       _num(all_tanks[i].find("contents"), "tank contents", src, "LBS", 0.0)) for i in fuel_idx)
    if not tanks or not sum(t.capacity_kg for t in tanks) > 0.0:
        raise AirframeError(f"aircraft: {src}: no fuel tank (propulsion/tank type FUEL with a capacity): the engines "
                            "burn from the aircraft's tanks")
    empty = _num(mb.find("emptywt"), "mass_balance/emptywt", src, "LBS")
    cg = _xyz(next((loc for loc in mb.findall("location") if loc.get("name", "CG") == "CG"), None),
              "mass_balance CG location", src, "IN")
    inertia = tuple(_num(mb.find(n), f"mass_balance/{n}", src, "SLUG*FT2", 0.0) for n in ("ixx", "iyy", "izz"))
    wheels = [(_xyz(c.find("location"), "contact location", src, "IN")[2],
               _num(c.find("spring_coeff"), "contact spring_coeff", src, "LBS/FT"))
              for c in (gr.findall("contact") if gr is not None else [])
              if (c.get("type") or "BOGEY") == "BOGEY" and c.find("spring_coeff") is not None]
    if not wheels:
        raise AirframeError(f"aircraft: {src}: no wheel (ground_reactions/contact type BOGEY): it cannot start on "
                            "a runway")
    side = _sidecar(folder)
    mass0 = empty + sum(t.contents_kg for t in tanks)
    rest, on_wheels = _rest_height(wheels, cg[2], mass0)
    tmp = _tmp_root() / key[1][:16]
    dest = tmp / "aircraft" / src.stem
    _rewrite(root, prop, mb, thrusters, cg)  # type: ignore[arg-type]
    _mirror(folder, dest, src.name)
    stock = _stock_root() or OWN_ROOT
    ac = Aircraft(src.stem, src, tmp, stock / "engine", stock / "systems", empty, cg,
                  (inertia[0], inertia[1], inertia[2]), tanks, thrusters,
                  _num(metrics.find("wingspan"), "metrics/wingspan", src, "FT"),
                  side.get("rest_cg_height_m", rest), on_wheels, side.get("mtom_kg"), fuel_idx,
                  len(mb.findall("pointmass")) - 1)
    _declare_missing(tree, root, dest / f"{src.stem}.xml", ac)
    _PREPARED[key] = ac
    return ac


def _rewrite(root: ET.Element, prop: ET.Element, mb: ET.Element, thrusters: tuple[Thruster, ...],
             cg: tuple[float, float, float]) -> None:
    """Engines out, thrust forces and the payload point mass in, the file's own inputs and outputs (sockets,
    files JSBSim would write) out (in place)."""
    for io in root.findall("input") + root.findall("output"):
        root.remove(io)
    ext = root.find("external_reactions")
    if ext is None:
        ext = ET.Element("external_reactions")
        root.insert(list(root).index(prop), ext)
    taken = {f.get("name") for f in ext.findall("force")}
    for i, (e, t) in enumerate(zip(prop.findall("engine"), thrusters, strict=True)):
        if t.force in taken:
            raise AirframeError(f"aircraft: the file already has an external force named '{t.force}', the name the "
                                "convention gives engine " + str(i + 1))
        th = e.find("thruster")
        where = th if th is not None and th.find("location") is not None else e
        f = ET.SubElement(ext, "force", {"name": t.force, "frame": "BODY", "unit": "LBS"})
        f.append(where.find("location"))  # type: ignore[arg-type]
        d = ET.SubElement(f, "direction")
        for c, v in zip("xyz", t.direction, strict=True):
            ET.SubElement(d, c).text = repr(v) if v not in (0.0, 1.0) else str(int(v))
        prop.remove(e)
    pm = ET.SubElement(mb, "pointmass", {"name": PAYLOAD_POINTMASS})
    ET.SubElement(pm, "weight", {"unit": "KG"}).text = "0"
    loc = ET.SubElement(pm, "location", {"unit": "M"})
    for c, v in zip("xyz", cg, strict=True):
        ET.SubElement(loc, c).text = repr(v)


def _mirror(folder: Path, dest: Path, skip: str) -> None:
    """``dest`` with a link to (or a copy of) every entry of ``folder`` but ``skip``."""
    if dest.exists():
        shutil.rmtree(dest)
    dest.mkdir(parents=True)
    for p in folder.iterdir():
        if p.name == skip:
            continue
        try:
            (dest / p.name).symlink_to(p, target_is_directory=p.is_dir())
        except OSError:  # pragma: no cover - a file system without links
            (shutil.copytree if p.is_dir() else shutil.copy2)(p, dest / p.name)


def _declare_missing(tree: ET.ElementTree, root: ET.Element, out: Path, ac: Aircraft) -> None:
    """Write the file; declare 0 every property its systems read that the removed engines defined (found by
    loading it, starting it on the ground and in the air, and flying a few frames, until none is missing)."""
    decl = ET.Element("system", {"name": "openEMSS: properties of the removed engines (0)"})
    prop = root.find("propulsion")
    root.insert(list(root).index(prop) + 1 if prop is not None else len(root), decl)
    with _quiet():
        _discover(tree, decl, out, ac)


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """JSBSim's own messages (to the process's stdout and stderr) silenced: those of the discovery are expected."""
    saved = []
    try:
        for fd in (1, 2):
            saved.append((fd, os.dup(fd)))
        null = os.open(os.devnull, os.O_WRONLY)
        for fd, _ in saved:
            os.dup2(null, fd)
        os.close(null)
    except OSError:  # pragma: no cover - no file descriptors to redirect (an embedding host)
        pass
    try:
        yield
    finally:
        _flush_c_stdio()  # JSBSim writes through C++ streams synchronised with C's stdio: out before the restore
        for fd, copy in saved:
            os.dup2(copy, fd)
            os.close(copy)


def _flush_c_stdio() -> None:
    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):  # pragma: no cover - no C library to flush (not on Linux or macOS)
        pass


def _discover(tree: ET.ElementTree, decl: ET.Element, out: Path, ac: Aircraft) -> None:
    import jsbsim

    for _ in range(_DISCOVERY_ROUNDS):
        tree.write(out, encoding="utf-8", xml_declaration=True)
        fdm = jsbsim.FGFDMExec(str(ac.root), None)
        fdm.set_debug_level(0)
        try:
            if not fdm.load_model_with_paths(ac.name, str(ac.root / "aircraft"), str(ac.engine_path),
                                             str(ac.systems_path)):
                raise AirframeError(f"aircraft: JSBSim could not load {ac.source}")
            pm = fdm.get_property_manager()
            for p in COMMAND_PROPERTIES:
                pm.get_node(p, True)
            for agl_ft, u_fps in ((ac.cg_height_on_wheels_m / _FT, 0.0), (3000.0, 250.0)):
                fdm["ic/h-agl-ft"], fdm["ic/u-fps"] = agl_ft, u_fps
                fdm.run_ic()
                for _ in range(10):
                    fdm.run()
            return
        except Exception as exc:  # noqa: BLE001 - JSBSim's errors are not one class; the missing ones are named
            m = _MISSING.search(str(exc))
            if m is None:
                raise AirframeError(f"aircraft: JSBSim could not fly {ac.source}: {str(exc).strip()}") from None
            ET.SubElement(decl, "property", {"value": "0"}).text = m.group(1)
        finally:
            del fdm
    raise AirframeError(f"aircraft: {ac.source}: its systems read more than {_DISCOVERY_ROUNDS} properties of its "
                        "engines")
