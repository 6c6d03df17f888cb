"""The compiled renderer: TinyRenderer's pipeline and the analytic hall, in numba."""
