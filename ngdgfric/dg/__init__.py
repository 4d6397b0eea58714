"""The DG discretisation of Section 3: the method table, the forms, the liftings, the material on each edge.

Data path: :mod:`~ngdgfric.dg.methods` (the table of the five methods and the conforming baseline) ->
:mod:`~ngdgfric.dg.material` (Lamé data per element and per edge) -> :mod:`~ngdgfric.dg.forms` and
:mod:`~ngdgfric.dg.liftings` (one form builder for all methods, (3.2)-(3.3); the liftings from the moments and
kernels of :mod:`~ngdgfric.dg.moments`, added into the matrix by element blocks, :mod:`~ngdgfric.dg.blocks`) ->
:mod:`~ngdgfric.dg.discretization` (the space, the assembled linear part and the contact data of one
problem on one mesh), which the solvers of :mod:`ngdgfric.solvers` take; :mod:`~ngdgfric.dg.dofs` counts the
DOFs of :math:`V_h`.
"""
