"""The contact surface shared by the solid and the film: its state
(:class:`~dolfinx_seal.surface.state.SurfaceState`), the follower tractions on the
deformed surface (:mod:`~dolfinx_seal.surface.tractions`) and the asperity contact
pressure and real-area fraction in UFL (:mod:`~dolfinx_seal.surface.asperity`).

The layer below ``solid`` and ``film``: both import from it, neither imports the other.
"""
