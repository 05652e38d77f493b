"""Models: one subpackage per model family, each with its private numba kernels beside it.

- :mod:`nsdyn.models.isolated` — frames on friction isolators (seed 004): constrained equations
  ``M q̈ + C q̇ + K q = −M Γ ü + Rᵀλ − Dᵀ μ s λ``, Baumgarte, friction laws, model ladder.
"""
