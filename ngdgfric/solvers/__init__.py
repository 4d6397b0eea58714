r"""The contact solvers of (3.3): semismooth Newton on :math:`\Gamma_C` (default), Uzawa, fixed point (:math:`m_t > 0`).

Data path: :mod:`~ngdgfric.contact.traces` (displacement traces at the contact Gauss points) ->
:mod:`~ngdgfric.solvers.condensation` (the Delassus operator :math:`W = B A^{-1} B^T`, PARDISO or
back-substitutions) -> :mod:`~ngdgfric.solvers.reduced` (the laws at the Gauss points, their residual and
Jacobian) -> :mod:`~ngdgfric.solvers.semismooth` (the globalised Newton iteration) ->
:mod:`~ngdgfric.solvers.newton` (the solver :func:`ngdgfric.solve` calls), which ends with the forces of
:mod:`~ngdgfric.solvers.selection` where the points are redundant.  :mod:`~ngdgfric.solvers.uzawa` (with
:mod:`~ngdgfric.solvers.nonlinear`) is the paper's algorithm (Section 6), :mod:`~ngdgfric.solvers.fixed_point` the
outer loop for :math:`m_t > 0`.  Each solver's options are a frozen dataclass (:mod:`~ngdgfric.solvers.options`).
"""
