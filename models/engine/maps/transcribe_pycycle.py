"""Transcribe pyCycle's map modules into the JSON files of this folder.

Run from the repository root with a local copy of OpenMDAO/pyCycle::

    python models/engine/maps/transcribe_pycycle.py /path/to/pyCycle/git-dir

It reads each map module with ``git show <commit>:<path>`` (the commit is
fixed below), keeps a verbatim copy under ``pycycle_src/`` and parses the
numbers with :mod:`ast` (``ast.literal_eval`` of the literal lists passed to
``np.array``); no number is typed by hand. Only the first plane of the
``alphaMap`` axis is kept (see README.md). Not imported by the model.
"""

from __future__ import annotations

import csv
import importlib.util
import io
import json
import subprocess
import sys
from pathlib import Path

_spec = importlib.util.spec_from_file_location("pycycle_module", Path(__file__).resolve().parent.parent
                                               / "pycycle_module.py")
assert _spec is not None and _spec.loader is not None
_mod = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_mod)
parse_map_module = _mod.parse_map_module    # the one parser of pyCycle's map modules (models/engine/pycycle_module.py)

REPO = "https://github.com/OpenMDAO/pyCycle"
COMMIT = "65faca6c95506122812f74a3e66079266327d95e"
HERE = Path(__file__).resolve().parent

# file name -> (map name, kind, component it is meant for, upstream name in the module's docstring)
MAPS = {
    "LPC_map.py": ("lpc_hbtf", "compressor", "fan / LPC (2 stages)", "HBTF LPC map of NPSS"),
    "axi5.py": ("axi5", "compressor", "HPC (4 stages)", "axi-5.map of NPSS"),
    "hpt1269.py": ("hpt1269", "turbine", "HPT (1 stage)", "hpt1269.map of NPSS"),
    "lpt2269.py": ("lpt2269", "turbine", "LPT (1 stage)", "lpt2269.map of NPSS"),
}


def to_json(obj: object, indent: str = "") -> str:
    """JSON text with every list of numbers on one line (one map row per line)."""
    inner = indent + "  "
    if isinstance(obj, dict):
        items = [f"{inner}{json.dumps(k)}: {to_json(v, inner)}" for k, v in obj.items()]
        return "{\n" + ",\n".join(items) + "\n" + indent + "}"
    if isinstance(obj, list) and obj and isinstance(obj[0], list):
        return "[\n" + ",\n".join(inner + to_json(v, inner) for v in obj) + "\n" + indent + "]"
    return json.dumps(obj)


# pyCycle's regression data: NPSS results at off-node map points (map columns only are kept).
REFERENCE = {
    "pycycle/elements/test/reg_data/compressorOD1.csv": (
        "npss_axi5_points.csv", ["comp.NcMap", "comp.RlineMap", "comp.WcMap", "comp.PRmap", "comp.effMap",
                                 "comp.SMW", "comp.SMN"]),
    "pycycle/elements/test/reg_data/turbineOD1.csv": (
        "npss_lpt2269_points.csv", ["turb.NpMap", "turb.PRmap", "turb.WpMap", "turb.effMap"]),
}


def transcribe_reference(git_dir: str) -> None:
    """Copy the map columns of pyCycle's NPSS regression files, text of each field unchanged."""
    (HERE / "reference").mkdir(exist_ok=True)
    for path, (out_name, columns) in REFERENCE.items():
        text = subprocess.run(["git", "--git-dir", git_dir, "show", f"{COMMIT}:{path}"],
                              check=True, capture_output=True, text=True).stdout
        rows = list(csv.reader(io.StringIO(text)))
        idx = [rows[0].index(c) for c in columns]
        lines = [f"# source: {REPO} {path} at commit {COMMIT} (Apache-2.0); columns {', '.join(columns)}"]
        lines += [",".join(columns)] + [",".join(r[i] for i in idx) for r in rows[1:] if r]
        (HERE / "reference" / out_name).write_text("\n".join(lines) + "\n", encoding="utf-8")
        print(f"{path} -> reference/{out_name}")


def main(git_dir: str) -> None:
    for fname, (name, kind, component, upstream) in MAPS.items():
        path = f"pycycle/maps/{fname}"
        text = subprocess.run(["git", "--git-dir", git_dir, "show", f"{COMMIT}:{path}"],
                              check=True, capture_output=True, text=True).stdout
        verbatim = HERE / "pycycle_src" / (fname + ".txt")
        verbatim.write_text(text, encoding="utf-8")
        d = parse_map_module(text)
        dflt = d["defaults"]
        common = {
            "name": name,
            "kind": kind,
            "component": component,
            "source": {"repository": REPO, "commit": COMMIT, "path": path,
                       "verbatim_copy": f"pycycle_src/{fname}.txt", "licence": "Apache-2.0",
                       "upstream": upstream},
        }
        if kind == "compressor":
            alpha = d["alphaMap"][0]  # type: ignore[index]
            rec = {
                **common,
                "alpha_plane": {"alphaMap": alpha, "index": 0},
                "speed": {"name": "NcMap", "values": d["NcMap"], "design": dflt["NcMap"]},
                "line": {"name": "RlineMap", "values": d["RlineMap"], "design": dflt["RlineMap"],
                         "surge": d["RlineStall"]},
                "tables": {"WcMap": d["WcMap"][0], "PRmap": d["PRmap"][0],  # type: ignore[index]
                           "effMap": d["effMap"][0]},  # type: ignore[index]
                "units": {"NcMap": "-", "RlineMap": "-", "WcMap": "lbm/s", "PRmap": "-", "effMap": "-"},
            }
        else:
            alpha = d["alphaMap"][0]  # type: ignore[index]
            rec = {
                **common,
                "alpha_plane": {"alphaMap": alpha, "index": 0},
                "speed": {"name": "NpMap", "values": d["NpMap"], "design": dflt["NpMap"]},
                "line": {"name": "PRmap", "values": d["PRmap"], "design": dflt["PRmap"]},
                "tables": {"WpMap": d["WpMap"][0], "effMap": d["effMap"][0]},  # type: ignore[index]
                "units": {"NpMap": "rpm/sqrt(degR), arbitrary scale", "PRmap": "-",
                          "WpMap": "lbm*sqrt(degR)/(s*psia)", "effMap": "-"},
            }
        out = HERE / f"{name}.json"
        out.write_text(to_json(rec) + "\n", encoding="utf-8")
        print(f"{path} -> {out.name}")
    transcribe_reference(git_dir)


if __name__ == "__main__":
    main(sys.argv[1])
