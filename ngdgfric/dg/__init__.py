"""The DG discretisation of Section 3: the method table, the forms, the liftings, the material on each edge.

Data path: :mod:`~ngdgfric.dg.methods` (the table of the five methods and the conforming baseline) ->
:mod:`~ngdgfric.dg.material` (Lamé data per element and per edge) -> :mod:`~ngdgfric.dg.forms` and
:mod:`~ngdgfric.dg.liftings` (one form builder for all methods, (3.2)-(3.3); the liftings from the moments and
kernels of :mod:`~ngdgfric.dg.moments`, added into the matrix by element blocks, :mod:`~ngdgfric.dg.blocks`) ->
:mod:`~ngdgfric.dg.discretization` (the space and the assembled linear part of one problem on one mesh), which the
solvers of :mod:`ngdgfric.solvers` take with the contact data of that mesh (:class:`ngdgfric.Contact`, built
beside it); :mod:`~ngdgfric.dg.dofs` counts the DOFs of :math:`V_h`.
"""
