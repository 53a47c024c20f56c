"""Type stubs of ``woven.mitsuba``."""

from typing import Any

import woven

def register(symbolic: bool = False) -> None:
    """Registers the ``woven`` BSDF and the ``woven_path`` integrator with Mitsuba for the
    current variant."""

class JitTable:
    """A woven table in Dr.Jit arrays; eval/pdf/sample_direction as Dr.Jit code."""

    def __init__(self, table: woven.Table, mi: Any) -> None: ...
    def eval(self, s: Any, v: Any, active: Any = True) -> Any: ...
    def eval_dyed(
        self, s: Any, v: Any, diffuse: Any, interreflection: Any, active: Any = True
    ) -> Any: ...
    def pdf(self, s: Any, v: Any, active: Any = True) -> Any: ...
    def sample_direction(self, s: Any, u1: Any, u2: Any, active: Any = True) -> Any: ...

def __getattr__(name: str) -> Any: ...
