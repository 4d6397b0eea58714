"""The two test problems of Section 6 and the shipped example scenes, loaded from the problem files
shipped with the package (``ngdgfric/data/example_6_1.toml``, ``example_6_2.toml``: the one source of
their data, also what ``ngdgfric solve 6.1`` reads; the scenes ``data/<name>.toml``, format in
:mod:`ngdgfric.problem_file`)."""

from .problem_file import PAPER_EXAMPLES, example_file, load_problem, shipped_files

__all__ = ["example_6_1", "example_6_2", "EXAMPLES", "SCENES", "example"]


def example_6_1():
    """Example 6.1: Omega = (0, 1) x (0.05, 1.05).

    Gamma_D = {1} x (0.05, 1.05), Gamma_F = ({0} x (0.05, 1.05)) u ((0, 1) x {1.05}),
    Gamma_C = (0, 1) x {0.05}; E = 2000, nu = 0.4, f = 0, g = (200 (5 - y), -190)
    on all of Gamma_F, c_tau = 450, c_n = 1, m_n = 1, g_a = 0.05.
    """
    return load_problem(example_file("6.1"))


def example_6_2():
    """Example 6.2: Omega = (0, 1)^2.

    Gamma_D = (0, 1) x {1}, Gamma_F = ({0} x (0, 1)) u ({1} x (0, 1)), Gamma_C = (0, 1) x {0};
    E = 2500, nu = 0.2, f = 0, g = (880, 0) on both sides of Gamma_F (taken literally),
    c_tau = 250, c_n = 1, g_a = 0, m_n = 1.
    """
    return load_problem(example_file("6.2"))


# the paper's examples (also the names the command line takes instead of a file)
EXAMPLES = {"6.1": example_6_1, "6.2": example_6_2}
# the shipped scenes, by the stem of their file in ngdgfric/data (each file's comment describes it):
# half_disk, block_with_hole, two_materials_symmetric, indentation, rubber_pad
SCENES = tuple(name for name in shipped_files() if name not in PAPER_EXAMPLES)


def example(name):
    """The problem of Example ``name`` ("6.1" or "6.2") or of a shipped scene ("half_disk", ... :data:`SCENES`);
    ValueError naming the choices otherwise."""
    key = str(name)
    if key in EXAMPLES:
        return EXAMPLES[key]()
    if key in SCENES:
        return load_problem(example_file(key))
    raise ValueError(f"example must be one of {sorted(EXAMPLES) + sorted(SCENES)}, got {name!r}")
