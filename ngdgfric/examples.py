"""The two test problems of Section 6 and the shipped example scenes.

They are loaded from the problem files shipped with the package (``example_6_1.toml``, ``example_6_2.toml``
in the package's ``data`` folder: the one source of their data, also what ``ngdgfric solve 6.1`` reads; the
scenes ``<name>.toml`` there; format in :mod:`ngdgfric.problem_file`, paths by :func:`ngdgfric.example_file`).
"""

from .problem_file import PAPER_EXAMPLES, example_file, load_problem, shipped_files

__all__ = ["example_6_1", "example_6_2", "EXAMPLES", "SCENES", "example"]


def example_6_1():
    r"""Example 6.1 of the paper: a unit square above the foundation, a gap of 0.05.

    .. math::

        \Omega = (0, 1) \times (0.05, 1.05), \quad
        \Gamma_D = \{1\} \times (0.05, 1.05), \quad
        \Gamma_C = (0, 1) \times \{0.05\},

        \Gamma_F = (\{0\} \times (0.05, 1.05)) \cup ((0, 1) \times \{1.05\});

    :math:`E = 2000`, :math:`\nu = 0.4`, :math:`f = 0`, :math:`g = (200 (5 - y), -190)` on all of
    :math:`\Gamma_F`, :math:`c_\tau = 450`, :math:`c_n = 1`, :math:`m_n = 1`, :math:`g_a = 0.05`.

    Returns
    -------
    ContactProblem
        The problem, read from its shipped problem file (:func:`ngdgfric.example_file`).
    """
    return load_problem(example_file("6.1"))


def example_6_2():
    r"""Example 6.2 of the paper: a unit square on the foundation, pushed sideways.

    .. math::

        \Omega = (0, 1)^2, \quad
        \Gamma_D = (0, 1) \times \{1\}, \quad
        \Gamma_C = (0, 1) \times \{0\},

        \Gamma_F = (\{0\} \times (0, 1)) \cup (\{1\} \times (0, 1));

    :math:`E = 2500`, :math:`\nu = 0.2`, :math:`f = 0`, :math:`g = (880, 0)` on both sides of :math:`\Gamma_F`
    (taken literally), :math:`c_\tau = 250`, :math:`c_n = 1`, :math:`g_a = 0`, :math:`m_n = 1`.

    Returns
    -------
    ContactProblem
        The problem, read from its shipped problem file (:func:`ngdgfric.example_file`).
    """
    return load_problem(example_file("6.2"))


# the paper's examples (also the names the command line takes instead of a file)
EXAMPLES = {"6.1": example_6_1, "6.2": example_6_2}
# the shipped scenes, by the stem of their file in ngdgfric/data (each file's comment describes it):
# half_disk, block_with_hole, two_materials_symmetric, indentation, rubber_pad
SCENES = tuple(name for name in shipped_files() if name not in PAPER_EXAMPLES)


def example(name):
    """The problem of one of the paper's examples or of a shipped scene.

    Parameters
    ----------
    name : str
        ``"6.1"`` or ``"6.2"`` (:func:`ngdgfric.example_6_1`, :func:`ngdgfric.example_6_2`), or a shipped scene:
        ``"half_disk"``, ``"block_with_hole"``, ``"two_materials_symmetric"``, ``"indentation"``,
        ``"rubber_pad"``, ``"two_cylinders"`` (``ngdgfric.examples.SCENES``).

    Returns
    -------
    ContactProblem
        The problem, read from its shipped problem file (:func:`ngdgfric.example_file`).

    Raises
    ------
    ValueError
        If ``name`` is none of these; the message names the choices.

    Examples
    --------
    >>> problem = ndf.example("6.1")
    >>> problem.name
    'Example 6.1'
    >>> problem.sides("contact")
    ('contact',)
    >>> ndf.example("half_disk").geometry.curved
    True
    """
    key = str(name)
    if key in EXAMPLES:
        return EXAMPLES[key]()
    if key in SCENES:
        return load_problem(example_file(key))
    raise ValueError(f"example must be one of {sorted(EXAMPLES) + sorted(SCENES)}, got {name!r}")
