"""dolfinx_seal: soft lubricated contacts (lip seals, soft-EHL balls and cylinders) in FEniCSx.

Subpackages by concern:

* ``roughness``  -- power spectra, synthetic surfaces (numpy only)
* ``contact``    -- Persson and classic asperity-contact laws, flow factors (numpy only)
* ``friction``   -- viscoelastic rubber friction (numpy only)
* ``film``       -- Reynolds thin film, cavitation (DOLFINx)
* ``solvers``    -- the PETSc SNES wrapper, continuation (DOLFINx)
* ``scenes``     -- named physics set-ups and the run/sweep drivers
* ``compat``     -- every DOLFINx version difference
* ``mpi``, ``params``, ``output``, ``errors``, ``cli`` -- plumbing

Units are SI throughout.  Importing the package does not import DOLFINx.
"""

from dolfinx_seal.errors import ParameterError, SolverError

__all__ = ["ParameterError", "SolverError"]
__version__ = "0.1.0"
