"""Geometry shared by the mesher and the analytic models: the spall's cross-section and a
rigid roller's path over it (numpy only)."""
