"""`common.jit`'s disk cache: two copies of the same kernel package under different top-level packages (the
repository's ``openemss.models.engine`` and an FMU's vendored ``emss_engine_<hash>_lib.models.engine``) share
their compiled kernels, so that a machine compiles them once; a change of the code compiles again."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from openemss.models.common.jit import AVAILABLE

pytestmark = pytest.mark.skipif(not AVAILABLE, reason="numba absent: nothing is compiled or cached")

KERNEL = '''from openemss.models.common.jit import jit


@jit
def twice(x: float) -> float:
    return {k} * x
'''

PROBE = '''import importlib, json, sys
sys.path.insert(0, sys.argv[1])
mod = importlib.import_module(sys.argv[2] + ".models.kern.kernel")
value = mod.twice(1.5)
print(json.dumps({"value": value, "hits": sum(mod.twice.stats.cache_hits.values()),
                  "misses": sum(mod.twice.stats.cache_misses.values())}))
'''


def _copy(root: Path, top: str, k: float) -> None:
    pkg = root / top / "models" / "kern"
    pkg.mkdir(parents=True)
    for folder in (root / top, root / top / "models", pkg):
        (folder / "__init__.py").write_text("")
    (pkg / "kernel.py").write_text(KERNEL.format(k=k))


def _probe(root: Path, top: str, cache: Path) -> dict[str, float]:
    env = dict(os.environ, OPENEMSS_JIT_CACHE=str(cache))
    env.pop("OPENEMSS_NO_JIT", None)
    out = subprocess.run([sys.executable, "-c", PROBE, str(root), top], capture_output=True, text=True, env=env,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_copies_under_other_top_level_packages_share_the_compiled_kernels(tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    for top in ("repo_a", "emss_kern_0123456789_lib"):
        _copy(tmp_path / "src", top, 2.0)
    first = _probe(tmp_path / "src", "repo_a", cache)
    assert first == {"value": 3.0, "hits": 0, "misses": 1}        # compiled and written
    other = _probe(tmp_path / "src", "emss_kern_0123456789_lib", cache)
    assert other == {"value": 3.0, "hits": 1, "misses": 0}        # the other copy's kernel, from the disk


def test_changed_code_is_compiled_again(tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    _copy(tmp_path / "a", "repo_a", 2.0)
    _copy(tmp_path / "b", "repo_b", 3.0)                          # same names, other code
    assert _probe(tmp_path / "a", "repo_a", cache)["misses"] == 1
    changed = _probe(tmp_path / "b", "repo_b", cache)
    assert changed == {"value": 4.5, "hits": 0, "misses": 1}      # not the stale 2 * x
