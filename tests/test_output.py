"""Output files and plots (ngdgfric.output): what they show is what the solution says."""

import xml.etree.ElementTree as ET

import matplotlib.colors
import matplotlib.image
import ngsolve as ngs
import numpy as np
import pytest

import ngdgfric as ndf
from ngdgfric.contact.forces import contact_sides
from ngdgfric.domain import Domain, Loop
from ngdgfric.meshes import mesh_arrays
from ngdgfric.output import (
    ZONE_STYLE,
    colour_cap,
    figure,
    plot_contact,
    plot_deformed,
    plot_estimator,
    plot_zones,
    uniform_markdown,
    vertex_values,
    write_contact_png,
    write_png,
    write_vtk,
)
from ngdgfric.problem import von_mises


@pytest.fixture(scope="module")
def solution():
    """SIPG P1 on Example 6.1, h = 1/4: Gamma_C has both slipping and sticking Gauss points."""
    problem = ndf.example_6_1()
    return ndf.solve(problem, ndf.uniform_mesh(problem, 0.25))


def triangle_areas(mesh):
    points, triangles = mesh_arrays(mesh)[:2]
    a, b, c = (points[triangles[:, k]] for k in range(3))
    (x1, y1), (x2, y2) = (b - a).T, (c - a).T
    return 0.5 * np.abs(x1 * y2 - x2 * y1)


@pytest.mark.parametrize("fraction", [0.5, 0.9, 0.99])
def test_colour_cap_leaves_the_fraction_of_the_area_below(fraction):
    mesh = ngs.Mesh(ngs.unit_square.GenerateMesh(maxh=0.15))  # triangles of different areas
    values = ngs.GridFunction(ngs.L2(mesh, order=0))
    values.vec.FV().NumPy()[:] = np.random.default_rng(1).permutation(mesh.ne)  # element means, all distinct
    cap = colour_cap(values, mesh, fraction)
    value = round(cap)  # the mean of one element (integrated, so up to round-off)
    assert cap == pytest.approx(value, abs=1e-9)
    area, means = triangle_areas(mesh), values.vec.FV().NumPy()
    assert area[means < value].sum() < fraction * area.sum() <= area[means <= value].sum()
    assert colour_cap(ngs.CF(7.5), mesh, fraction) == pytest.approx(7.5, rel=1e-12)


def test_vertex_values_are_each_elements_own_values():
    mesh = ndf.uniform_mesh(ndf.example_6_2(), 0.25)
    jump = ngs.GridFunction(ngs.L2(mesh, order=0))  # a different affine function on every element
    jump.vec.FV().NumPy()[:] = np.arange(mesh.ne)
    u = ngs.GridFunction(ngs.VectorL2(mesh, order=1))
    u.Set(ngs.CF((ngs.x + 2 * ngs.y + jump, jump * ngs.x)))
    xy, values = vertex_values(mesh, u)
    points, triangles = mesh_arrays(mesh)[:2]
    assert np.allclose(np.sort(xy, axis=1), np.sort(points[triangles], axis=1), atol=1e-14)
    element = np.arange(mesh.ne)[:, None]
    assert np.allclose(values[..., 0], xy[..., 0] + 2 * xy[..., 1] + element, atol=1e-10)
    assert np.allclose(values[..., 1], element * xy[..., 0], atol=1e-10)


def test_default_deformation_draws_the_largest_displacement_as_at_most_a_tenth_of_the_domain(solution):
    ax = figure(6, 5).add_subplot()
    scale = plot_deformed(ax, solution)
    (cells,) = ax.collections
    xy, u = vertex_values(solution.mesh, solution.u)
    drawn = np.array([path.vertices[:3] for path in cells.get_paths()])
    assert np.allclose(drawn, xy + scale * u, rtol=1e-12, atol=1e-12)
    # a round magnification (1, 2 or 5 times a power of ten): the largest displacement drawn as 4 % to 10 % of
    # Omega (1 x 1), the largest such round number
    mantissa = scale / 10.0 ** np.floor(np.log10(scale) + 1e-12)
    assert min(abs(mantissa - step) for step in (1, 2, 5)) < 1e-9
    largest = np.max(np.linalg.norm(drawn - xy, axis=2))
    assert 0.04 <= largest <= 0.1 * (1 + 1e-12) and largest * {1: 2, 2: 2.5, 5: 2}[round(mantissa)] > 0.1
    assert ax.get_title().endswith(f"displacement \N{MULTIPLICATION SIGN} {scale:g}")
    assert plot_deformed(figure(6, 5).add_subplot(), solution, scale=2.0) == 2.0
    ax = figure(6, 5).add_subplot()
    plot_deformed(ax, solution, scale=0)
    assert ax.get_title().endswith(", undeformed")  # not "displacement x 0"


def test_deformed_plot_caps_the_colour_range_where_one_percent_of_the_area_lies_above():
    problem = ndf.example_6_1()
    sol = ndf.solve(problem, ndf.uniform_mesh(problem, 1 / 16))  # elements of 0.2 % of the area each
    ax = figure(6, 5).add_subplot()
    plot_deformed(ax, sol)
    (cells,) = ax.collections
    means, (low, cap) = cells.get_array(), cells.get_clim()
    areas = triangle_areas(sol.mesh)
    assert low == means.min() and cap < means.max()  # Example 6.1: the stress of its corners stands out
    assert areas[means > cap].sum() <= 0.01 * areas.sum() < areas[means >= cap].sum()
    assert ax.figure.axes[-1].get_label() == "<colorbar>" and cells.colorbar.extend == "max"


def test_deformed_plot_draws_the_outline_of_a_curved_domain_with_a_hole_and_the_zones():
    disk = Loop([(-1, 1), (1, 1)], ["contact", "lid"], arcs={0: (0.0, 0.0)})
    hole = Loop.circle((0, 0.6), 0.2, "hole")
    problem = ndf.ContactProblem(E=1.0, nu=0.3, f=(0.01, 0), g=(0, 0), c_n=1e2, m_n=1, g_a=0.01 * ngs.y, c_tau=0.05,
                                 geometry=Domain({"omega": disk}, holes=(hole,)), dirichlet="lid", traction="hole",
                                 u_D=(0.0, -0.02))
    sol = ndf.solve(problem, ndf.netgen_mesh(problem, 0.3), order=2)
    ax = figure(6, 5).add_subplot()
    plot_deformed(ax, sol)
    lines = ax.get_lines()
    dashed = [line.get_xydata() for line in lines if line.get_linestyle() == "--"]
    outline = problem.geometry.outline()
    assert len(dashed) == len(outline) == 2  # the half disk (its arc sampled) and the hole
    for drawn, curve in zip(dashed, outline, strict=True):
        assert np.array_equal(drawn, curve)
    assert np.linalg.norm(dashed[1] - (0, 0.6), axis=1) == pytest.approx(0.2, rel=1e-12)
    side = contact_sides(sol)["contact"]
    for name in ZONE_STYLE:  # each zone's pieces drawn in its colour, one legend entry per zone
        zone = getattr(side, name)
        drawn = [line.get_xydata() for line in lines if line.get_color() == ZONE_STYLE[name]["color"]]
        assert len(drawn) == len(zone.pieces) > 0
        assert all(np.array_equal(a, b) for a, b in zip(drawn, zone.pieces, strict=True))
    assert {text.get_text() for text in ax.get_legend().get_texts()} == {
        "undeformed", "contact zone", "stick zone", "slip zone"}


def test_zone_plot_shades_the_stick_and_slip_zones_along_the_side(solution, tmp_path):
    side = contact_sides(solution)["contact"]
    ax = figure(7, 3).add_subplot()
    twin = plot_zones(ax, solution, "contact")
    state = ndf.contact_state(solution)
    pressure = [line for line in ax.get_lines() if line.get_marker() == "."]
    assert len(pressure) == 1 and np.array_equal(pressure[0].get_xdata(), side.arc)
    assert np.array_equal(pressure[0].get_ydata(), state["pressure"][side.points])
    (lam_tau,) = twin.get_lines()
    assert np.array_equal(lam_tau.get_ydata(), np.abs(state["lam_tau"][side.points]))
    shaded = {}
    for patch in ax.patches:  # axvspan: a rectangle from x to x + width
        colour = patch.get_facecolor()[:3]
        shaded[colour] = shaded.get(colour, 0.0) + patch.get_width()
    blue, red = (matplotlib.colors.to_rgb(ZONE_STYLE[name]["color"]) for name in ("stick", "slip"))
    assert shaded[blue] == pytest.approx(side.stick.length, rel=1e-12) and side.stick.length > 0
    assert shaded[red] == pytest.approx(side.slip.length, rel=1e-12) and side.slip.length > 0
    band = [line for line in ax.get_lines() if line.get_color() == ZONE_STYLE["contact"]["color"]]
    assert sum(np.ptp(line.get_xdata()) for line in band) == pytest.approx(side.contact.length, rel=1e-12)
    write_contact_png(tmp_path / "c.png", solution)
    assert matplotlib.image.imread(tmp_path / "c.png").shape[:2] == (int(110 * 3.2), 110 * 7)  # one contact side


@pytest.mark.parametrize("p", [1, 2, 3])
def test_the_reference_slope_is_the_optimal_rate(p):
    ndof = np.array([50.0, 200.0, 800.0, 3200.0])
    optimal = [dict(ndof=n, eta_h=3.0 * n ** (-p / 2)) for n in ndof]  # eta_h ~ N^{-p/2} exactly
    slower = [dict(ndof=n, eta_h=3.0 * n ** (-p / 4)) for n in ndof]
    ax = figure(5, 4).add_subplot()
    plot_estimator(ax, {"optimal": optimal, "slower": slower}, slope=(optimal, p))
    curve, other, reference = ax.get_lines()
    assert [line.get_marker() for line in (curve, other)] == ["o", "s"]
    assert np.array_equal(curve.get_xdata(), ndof) and np.array_equal(other.get_xdata(), ndof)
    assert np.allclose(reference.get_ydata(), curve.get_ydata(), rtol=1e-12)
    assert np.polyfit(np.log(other.get_xdata()), np.log(other.get_ydata()), 1)[0] == pytest.approx(-p / 4)
    assert reference.get_label() == f"$N^{{-{p}/2}}$"


def tick_labels(fig, axis):
    """The window extents of the non-empty tick labels of ``axis`` that lie in its view."""
    fig.canvas.draw()
    low, high = sorted(axis.get_view_interval())
    ticks = [tick for tick in axis.get_major_ticks() + axis.get_minor_ticks()
             if low <= tick.get_loc() <= high and tick.label1.get_visible() and tick.label1.get_text()]
    return [tick.label1.get_window_extent() for tick in ticks]


@pytest.mark.parametrize("ndof, eta_h", [
    ([48, 60, 84], [910.0, 832.0, 775.0]),  # a fifth of a decade each way: the smoke run of Example 6.1
    ([50, 110, 250, 700], [21.0, 15.0, 9.0, 4.5]),  # about one decade
    ([48, 3000, 20850], [910.0, 200.0, 78.0]),  # several decades
    ([970, 1140, 1370, 9500], [3.5e-3, 2.0e-1, 2.9e-2, 6.3e-6]),  # a narrow N, a wide eta_h
])
def test_estimator_axes_have_two_labels_each_and_none_overlap(ndof, eta_h):
    fig = figure(5, 4)
    ax = fig.add_subplot()
    plot_estimator(ax, {"eta_h": [dict(ndof=n, eta_h=e) for n, e in zip(ndof, eta_h, strict=True)]})
    for axis in (ax.xaxis, ax.yaxis):
        boxes = tick_labels(fig, axis)
        assert len(boxes) >= 2, [box.bounds for box in boxes]
        assert not any(a.overlaps(b) for k, a in enumerate(boxes) for b in boxes[k + 1:])


def test_contact_plot_shows_the_friction_law(solution):
    axes = figure(7, 9).subplots(4, 1, sharex=True)
    plot_contact(axes, solution)
    _, traction, bound, minus_bound = axes[1].get_lines()
    c_tau = solution.problem.c_tau
    assert np.all(bound.get_ydata() == c_tau) and np.all(minus_bound.get_ydata() == -c_tau)
    assert np.all(np.diff(traction.get_xdata()) >= 0)  # left to right
    assert np.all(np.abs(traction.get_ydata()) <= c_tau * (1 + 1e-12))  # |l| <= 1 (Lemma 3.1)
    contact, slip, stick = axes[3].get_lines()
    assert len(slip.get_xdata()) + len(stick.get_xdata()) == len(traction.get_xdata())
    assert len(slip.get_xdata()) > 0 and len(stick.get_xdata()) > 0
    slipping = np.isin(traction.get_xdata(), slip.get_xdata())
    assert np.allclose(np.abs(traction.get_ydata()[slipping]), c_tau, rtol=1e-8)  # slip: |l| = 1
    assert np.all(np.abs(traction.get_ydata()[~slipping]) < c_tau)


def read_vtu(path):
    """{name: array (entries, components)} of a VTK file as NGSolve's VTKOutput writes it (raw appended data,
    each array preceded by its size in bytes as UInt32)."""
    header, _, appended = path.read_bytes().partition(b'<AppendedData encoding="raw">')
    start = appended.index(b"_") + 1
    arrays = {}
    for array in ET.fromstring(header + b"</VTKFile>").iter("DataArray"):
        offset = start + int(array.get("offset"))
        dtype = np.dtype({"Float64": np.float64, "Int32": np.int32, "UInt8": np.uint8}[array.get("type")])
        size = int(np.frombuffer(appended, np.uint32, 1, offset)[0])
        values = np.frombuffer(appended, dtype, size // dtype.itemsize, offset + 4)
        arrays[array.get("Name")] = values.reshape(-1, int(array.get("NumberOfComponents", 1)))
    return arrays


def test_vtk_file_holds_the_displacement_and_its_von_mises_stress(solution, tmp_path):
    for other in ("u.vtk", "u"):  # NGSolve's writer appends .vtu: this was "OSError ... the writer produced no file"
        with pytest.raises(ValueError, match=f"write_vtk writes a .vtu file .*{other}'"):
            write_vtk(tmp_path / other, solution)
    write_vtk(tmp_path / "u.vtu", solution)
    assert [p.name for p in tmp_path.iterdir()] == ["u.vtu"]
    arrays = read_vtu(tmp_path / "u.vtu")
    mesh = solution.mesh
    cells = arrays["connectivity"].reshape(mesh.ne, 3)  # P1: no subdivision, one triangle per element
    area = ngs.Integrate(ngs.CF(1), mesh, element_wise=True).NumPy()[:, None]
    # the points of each cell are its element's vertices, the point data that element's own values
    mean_u = np.column_stack([ngs.Integrate(solution.u[k], mesh, element_wise=True).NumPy() for k in (0, 1)]) / area
    assert np.allclose(arrays["displacement"][cells].mean(axis=1), mean_u, rtol=1e-10, atol=1e-12)  # P1
    vm = ngs.Integrate(von_mises(solution.problem, solution.u), mesh, element_wise=True).NumPy()[:, None] / area
    assert np.allclose(arrays["von_mises"][cells][..., 0], vm, rtol=1e-10)  # constant strain on P1 triangles
    corners = np.sort(arrays["Points"][cells][..., :2], axis=1)
    points, triangles = mesh_arrays(mesh)[:2]
    assert np.allclose(corners, np.sort(points[triangles], axis=1), atol=1e-14)


def test_png_has_the_size_asked_for(tmp_path):
    fig = figure(3, 2)
    fig.add_subplot().plot([0, 1], [1, 0])
    write_png(fig, tmp_path / "f.png", dpi=50)
    assert matplotlib.image.imread(tmp_path / "f.png").shape[:2] == (100, 150)
    assert [p.name for p in tmp_path.iterdir()] == ["f.png"]


def test_uniform_markdown_table():
    rows = [dict(method="sipg", k=k, ndof=48 * 4**k, energy=2.0**-k, rate=None if k == 1 else 1.0,
                 eta_h=3.0 * 2.0**-k, iterations=k + 3, seconds=1.5 * k) for k in (1, 2)]
    title, blank, header, rule, *lines = uniform_markdown("Example 6.2: uniform meshes", rows).splitlines()
    assert (title, blank) == ("# Example 6.2: uniform meshes", "")
    assert header.startswith("| method | h | DOFs |") and rule == "|---" * 8 + "|"
    cells = [line.strip("| ").split(" | ") for line in lines]
    assert [c[:3] for c in cells] == [["sipg", "2^-1", "192"], ["sipg", "2^-2", "768"]]
    assert [c[4] for c in cells] == ["-", "1.000"]
    for row, c in zip(rows, cells, strict=True):
        assert float(c[3]) == pytest.approx(row["energy"], rel=1e-4)
        assert float(c[5]) == pytest.approx(row["eta_h"], rel=1e-4)
        assert (int(c[6]), float(c[7])) == (row["iterations"], pytest.approx(row["seconds"], abs=0.005))


def test_tex_number_writes_exponents_as_powers_of_ten():
    """The one number-to-TeX writer of the tick labels and the scenes' descriptions."""
    from ngdgfric.output import tex_number

    assert [tex_number(v) for v in (1e6, 2.5e-7, 0.5, 100000.0, -3e12)] == \
        ["10^{6}", r"2.5 \times 10^{-7}", "0.5", "100000", r"-3 \times 10^{12}"]
