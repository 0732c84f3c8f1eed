"""2-D plane-strain finite-element companion of the rigid DFP model (scikit-fem + gmsh)."""
