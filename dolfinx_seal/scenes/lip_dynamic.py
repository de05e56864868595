"""Scene ``lip-dynamic``: the periodic lip sector of ``lip-static`` on a turning shaft.

The shaft surface slides along the circumference at ``film.speed``; the film is
the mass-conserving JFO model (S0 eqs 10-11) with its partial-film shear (A.5),
on the lip frozen in its dry two-scale state (``feedback = false``), pressurised
at 1 mm/s and then solved at each speed from the last state.  Everything else,
and the module, is :mod:`dolfinx_seal.scenes.lip_sector`.
"""

from dolfinx_seal.scenes.lip_sector import DYNAMIC_SCENE as SCENE
from dolfinx_seal.scenes.lip_sector import LipDynamicParameters

__all__ = ["SCENE", "LipDynamicParameters"]
