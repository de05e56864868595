"""Thin-film lubrication: Reynolds fluxes and residuals, cavitation models."""
