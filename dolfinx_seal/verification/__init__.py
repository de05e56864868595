"""Independent reference solutions (numpy/scipy only, written apart from the FEM code)."""
