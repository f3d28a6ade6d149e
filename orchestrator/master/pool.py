"""FMU instances kept warm between runs of one process: fmi2Reset instead of a new fmi2Instantiate.

A study's worker runs case after case of the same FMUs (:mod:`openemss.study.warm`). Instantiating a
pythonfmu FMU imports its model and loads its compiled kernels, and a new process for each case pays
the interpreter and the imports as well: seconds per case. With the pool :func:`enabled`, a
:class:`.slave.Slave` whose run ended cleanly (``fmi2Terminate`` returned OK) hands its instance to the
pool instead of freeing it, and the next slave of the same FMU file (same path, size, modification
time and GUID) under the same instance name takes it and calls ``fmi2Reset``, which FMI 2.0 defines
as putting the instance back into the state right after ``fmi2Instantiate`` (section 2.1.6,
"fmi2Reset ... the FMU is in the same state as if fmi2Instantiate would have been called"); the run
then sets up, sets its parameters and initializes it as a new one. A failed, interrupted or fatal
instance is never pooled: it is freed as without the pool.

Whether an FMU's reset really returns it to its initial state is the FMU's promise; the study's test
runs the same case cold and warm (after another case) and compares every recorded column bit for bit
(``tests/study/test_warm_cases.py``).

The pool is off unless :func:`enable` is called (``emss run`` never pools); it lives as long as its
process.
"""
from __future__ import annotations

import collections
import os
from pathlib import Path
from typing import Any

__all__ = ["enable", "enabled", "take", "give", "clear", "counts", "PoolKey"]

PoolKey = tuple[str, int, int, str, str]  # FMU file (resolved), its size [B] and mtime [ns], GUID, instance name

_state: dict[str, Any] = {"enabled": False, "taken": 0, "given": 0}
_free: dict[PoolKey, collections.deque[Any]] = collections.defaultdict(collections.deque)


def key(fmu_path: Path | str, guid: str, instance_name: str) -> PoolKey:
    """The pool key of an instance of the FMU file ``fmu_path`` (a rebuilt FMU has another key)."""
    path = os.path.realpath(fmu_path)
    st = os.stat(path)
    return path, st.st_size, st.st_mtime_ns, guid, instance_name


def enable(on: bool = True) -> None:
    """Keep clean instances for the next run (on) or free them at the end of their run (off: the default)."""
    _state["enabled"] = bool(on)
    if not on:
        clear()


def enabled() -> bool:
    return bool(_state["enabled"])


def take(k: PoolKey) -> Any | None:
    """A pooled instance (fmpy ``FMU2Slave``, terminated, not yet reset) for key ``k``, or None."""
    q = _free.get(k)
    if not q:
        return None
    _state["taken"] += 1
    return q.popleft()


def give(k: PoolKey, fmu: Any) -> bool:
    """Keep ``fmu`` (terminated cleanly) for the next run; False when the pool is off (the caller frees it)."""
    if not _state["enabled"]:
        return False
    _free[k].append(fmu)
    _state["given"] += 1
    return True


def clear() -> None:
    """Free every pooled instance (never raises: an instance that refuses is dropped)."""
    for q in _free.values():
        while q:
            fmu = q.popleft()
            try:
                fmu.fmi2FreeInstance(fmu.component)
            except Exception:  # freeing is the last call; nothing more to do with one that refuses
                pass
    _free.clear()


def counts() -> dict[str, int]:
    """Instances taken from and given to the pool since the process started, and those held now."""
    return {"taken": int(_state["taken"]), "given": int(_state["given"]),
            "held": sum(len(q) for q in _free.values())}
