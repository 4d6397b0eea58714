"""Solver options: one frozen dataclass per solver, its values checked when it is built.

Each solver's options class (:class:`ngdgfric.NewtonOptions`, :class:`ngdgfric.UzawaOptions`,
:class:`ngdgfric.FixedPointOptions`) derives from :class:`ngdgfric.SolverOptions`; ``solve(**options)``
(:func:`ngdgfric.solve`) builds it with ``SolverOptions.from_keywords``, so an unknown name or a bad value
raises a ValueError naming it before anything is assembled.
"""

import dataclasses

__all__ = ["SolverOptions"]


class SolverOptions:
    """Base of the solvers' frozen option dataclasses.

    A subclass sets the class attributes ``solver`` (its name in messages) and ``checks`` (a dict from each
    field's name to ``check(value, name)``, which raises ValueError); every field is checked when an instance is
    built.  The subclasses: :class:`ngdgfric.NewtonOptions`, :class:`ngdgfric.UzawaOptions`,
    :class:`ngdgfric.FixedPointOptions`.

    Attributes
    ----------
    solver : str
        The solver's name in messages (class attribute).
    checks : dict
        ``{field name: check(value, name)}``, each check raising ValueError for a bad value (class attribute).

    See Also
    --------
    ngdgfric.solve : Builds the options of its ``solver`` from its keywords (``from_keywords``).
    """

    solver = ""
    checks = {}

    def __post_init__(self):
        for field in dataclasses.fields(self):
            self.checks[field.name](getattr(self, field.name), field.name)

    @classmethod
    def from_keywords(cls, solver=None, **options):
        """The options from keywords (e.g. those of :func:`ngdgfric.solve`); None means the default.

        Parameters
        ----------
        solver : str or None, optional
            The solver's name in the error message.  Default ``None``: ``cls.solver``.
        **options
            The fields as keywords; a value ``None`` means the field's default.

        Returns
        -------
        SolverOptions
            An instance of the class it is called on, its values checked.

        Raises
        ------
        ValueError
            An unknown name (the message lists the options of ``solver``) or a bad value.
        """
        known = sorted(field.name for field in dataclasses.fields(cls))
        for name in options:
            if name not in known:
                raise ValueError(f"solver {solver or cls.solver!r} has no option {name!r}; its options are {known}")
        return cls(**{name: value for name, value in options.items() if value is not None})
