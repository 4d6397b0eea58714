r"""The figures of the gallery: the deformed body, the contact laws and zones, meshes and estimator curves.

A user draws with it what the gallery and ``ngdgfric solve`` show:

* :func:`~ngdgfric.output.plot_deformed`: the elements moved by the magnified displacement :math:`u_h`,
  coloured by the von Mises stress (1.3), with the contact, stick and slip zones of :mod:`ngdgfric.forces`;
* :func:`~ngdgfric.output.plot_contact`: the contact quantities along :math:`\Gamma_C` with the laws (1.8) and
  (1.9) that they satisfy, the slip and the zones;
* :func:`~ngdgfric.output.plot_zones`: one contact side along its arc length, the pressure, :math:`|\lambda_\tau|`
  and the zones;
* :func:`~ngdgfric.output.plot_mesh` and :func:`~ngdgfric.output.plot_estimator` (the estimator
  :math:`\eta_h` of Section 4 against the number of DOFs);
* the files :func:`~ngdgfric.output.write_vtk` (for ParaView), :func:`~ngdgfric.output.write_deformed_png` and
  :func:`~ngdgfric.output.write_contact_png` (the PNGs of ``ngdgfric solve``).

The plots draw into matplotlib Axes that the caller makes: a notebook with ``plt.subplots``, the command line
with ``figure`` (no pyplot, nothing displayed)::

    import matplotlib.pyplot as plt
    from ngdgfric.output import plot_deformed

    fig, ax = plt.subplots(figsize=(8, 5))
    plot_deformed(ax, sol)

Files are written atomically through :mod:`ngdgfric.files` (a temporary file renamed into place;
CSV and plain text: ``write_csv`` and ``write_text`` there).  The module also makes the Markdown tables of the
scripts.
"""

from pathlib import Path

import ngsolve as ngs
import numpy as np

from .contact.forces import contact_sides
from .contact.pair_zones import all_sides
from .contact.state import contact_state
from .files import atomic_path
from .meshes import mesh_arrays
from .problem import von_mises

__all__ = ["figure", "write_png", "write_vtk", "markdown_table", "uniform_markdown", "rate_text", "colour_cap",
           "vertex_values", "plot_deformed", "write_deformed_png", "estimator_curve", "plot_estimator", "log_ticks",
           "tex_number", "plot_mesh", "write_adaptive_png", "plot_contact", "ZONE_STYLE", "plot_zone_marks",
           "plot_zones", "write_contact_png"]

ZONE_STYLE = {"contact": dict(color="0.55", lw=7, alpha=0.5), "stick": dict(color="tab:blue", lw=2.5),
              "slip": dict(color="tab:red", lw=2.5)}
"""How the zones of :mod:`ngdgfric.forces` are drawn (matplotlib line options): the contact zone as a wide grey
band, the stick and slip zones (which split the region where friction acts) as coloured lines over it."""


def figure(width, height):
    """A matplotlib Figure of ``width`` x ``height`` inches on an Agg canvas, without pyplot's global state."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height))
    FigureCanvasAgg(fig)
    return fig


def write_png(fig, path, dpi):
    """Lay out ``fig`` and write it as the PNG file ``path`` atomically."""
    fig.tight_layout()
    with atomic_path(path) as temporary:
        fig.savefig(temporary, dpi=dpi)


def write_vtk(path, sol):
    r"""Write :math:`u_h` and its von Mises stress (1.3) as the VTK file ``path`` (.vtu) atomically.

    Point data ``displacement`` and ``von_mises``; every element subdivided :math:`p - 1` times, so that
    :math:`P_p` is drawn by its values on a finer lattice.  For ParaView.

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write; it must end in ``.vtu``.
    sol : Solution
        A solution of :func:`ngdgfric.solve` (:class:`ngdgfric.Solution`).

    Raises
    ------
    ValueError
        A ``path`` not ending in ``.vtu`` (NGSolve's writer appends it: ``"out.vtk"`` would become
        ``"out.vtk.vtu"``).
    """
    if Path(path).suffix != ".vtu":
        raise ValueError(f"write_vtk writes a .vtu file (VTK unstructured grid), got the path {str(path)!r}")
    with atomic_path(path) as temporary:  # VTKOutput appends .vtu to the name it is given
        ngs.VTKOutput(sol.mesh, coefs=[sol.u, von_mises(sol.discretization.material, sol.u)],
                      names=["displacement", "von_mises"], filename=str(temporary.with_suffix("")),
                      subdivision=max(sol.max_order - 1, 0)).Do()


def markdown_table(header, rows):
    """A Markdown table: the cells ``header`` and one line per row of ``rows`` (each cell as str())."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(cell) for cell in row) + " |" for row in rows]
    return "\n".join(lines)


def rate_text(rate):
    """An observed convergence rate with three decimals, "-" where there is none (the first mesh)."""
    return "-" if rate is None else f"{rate:.3f}"


def uniform_markdown(title, rows):
    """The Markdown report of a uniform refinement study (Tables 6.1, 6.2), headed ``title``.

    ``rows``: the rows of ``ngdgfric.studies.uniform_study`` with ``method`` and ``eta_h`` added.
    """
    header = ["method", "h", "DOFs", "|||u_h - u_{h/2}|||_h", "rate", "eta_h", "iterations", "seconds"]
    cells = [(r["method"], f"2^-{r['k']}", r["ndof"], f"{r['energy']:.4e}", rate_text(r["rate"]), f"{r['eta_h']:.4e}",
              r["iterations"], f"{r['seconds']:.2f}") for r in rows]
    return f"# {title}\n\n" + markdown_table(header, cells) + "\n"


def colour_cap(cf, mesh, fraction=0.99):
    """The element mean of ``cf`` below which lie the means of a ``fraction`` of the area of ``mesh``.

    A colour range [0, cap] that the few elements at a singular corner, where the stress grows
    without bound, do not swamp.
    """
    area = ngs.Integrate(ngs.CF(1), mesh, element_wise=True).NumPy()
    return _area_quantile(ngs.Integrate(cf, mesh, element_wise=True).NumPy() / area, area, fraction)


def vertex_values(mesh, *cfs):
    """Each element's own values at its three vertices: (xy, values of each of ``cfs``) as arrays (ne, 3, dim).

    A DG function has one value per element at a vertex; these are the values of the element's polynomial.
    """
    points = mesh.MapToAllElements(ngs.IntegrationRule([(1, 0), (0, 1), (0, 0)], [0, 0, 0]), ngs.VOL)
    xy = np.column_stack([ngs.x(points).ravel(), ngs.y(points).ravel()]).reshape(mesh.ne, 3, 2)
    return (xy, *(np.asarray(cf(points)).reshape(mesh.ne, 3, cf.dim) for cf in cfs))


def plot_deformed(ax, sol, scale=None, sides=None):
    r"""Draw the deformed elements, coloured by the von Mises stress, with the contact, stick and slip zones.

    The triangles moved by ``scale`` :math:`u_h` (each by its own vertex values; every body with the same scale),
    coloured by the element's mean von Mises stress (1.3) up to the mean that 99 % of the area stays below (the
    few elements at a singular corner, where the stress grows without bound, do not take the whole colour range;
    the colour bar's arrow marks the cap), over the undeformed outline (every boundary and
    interface curve of the geometry, curved sides sampled), with the contact, stick and slip zones marked on the
    undeformed contact sides and on both sides of every contact pair (``plot_zone_marks``); a colour bar, a title
    that states the magnification (or "undeformed" for ``scale=0``) and a legend below the Axes, off the body.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The Axes to draw into.
    sol : Solution
        A solution of :func:`ngdgfric.solve` (:class:`ngdgfric.Solution`).
    scale : float or None, optional
        The displacement's magnification; 0 draws the reference configuration.  Default ``None``: the largest
        1, 2 or 5 times a power of ten that draws the largest displacement as at most 10 % of the domain's
        size.
    sides : dict or None, optional
        The contact sides of ``sol`` and the sides of its contact pairs (``all_sides`` of
        :mod:`ngdgfric.contact.pair_zones`, or :meth:`ngdgfric.ForceBalance.sides`), to share them between plots.
        Default ``None``: computed.

    Returns
    -------
    float
        The magnification used.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from ngdgfric.output import plot_deformed
    >>> problem = ndf.example_6_1()
    >>> sol = ndf.solve(problem, ndf.uniform_mesh(problem, 0.5))
    >>> fig, ax = plt.subplots(figsize=(8, 5))
    >>> scale = plot_deformed(ax, sol)
    >>> plt.close(fig)
    """
    from matplotlib.collections import PolyCollection

    problem, mesh = sol.problem, sol.mesh
    xy, u, stress = vertex_values(mesh, sol.u, von_mises(sol.discretization.material, sol.u))
    x0, y0, x1, y1 = problem.geometry.bounds
    largest = float(np.max(np.linalg.norm(u, axis=2)))
    if scale is None:
        scale = _round_scale(0.1 * max(x1 - x0, y1 - y0) / largest) if largest > 0 else 1.0
    for k, line in enumerate(problem.geometry.outline()):
        ax.plot(line[:, 0], line[:, 1], "k--", lw=0.8, label=None if k else "undeformed")
    means = stress[:, :, 0].mean(axis=1)
    cells = PolyCollection(xy + scale * u, array=means, cmap="viridis", edgecolors="k",
                           linewidths=0.2 if mesh.ne <= 5000 else 0)
    cap = _area_quantile(means, _triangle_areas(xy), 0.99)
    cells.set_clim(means.min(), cap)
    ax.add_collection(cells)
    plot_zone_marks(ax, all_sides(sol) if sides is None else sides)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.figure.colorbar(cells, ax=ax, label="von Mises stress", extend="max" if means.max() > cap else "neither")
    shown = "undeformed" if scale == 0 else f"displacement \N{MULTIPLICATION SIGN} {scale:g}"
    ax.set_title(f"{problem.name}: {sol.method} P{sol.max_order}, {sol.ndof} DOFs, {shown}", fontsize=9)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=4, frameon=False)
    return scale


def _triangle_areas(xy):
    """The areas of the straight triangles with the corners ``xy`` (ne, 3, 2)."""
    (x1, y1), (x2, y2) = (xy[:, 1] - xy[:, 0]).T, (xy[:, 2] - xy[:, 0]).T
    return 0.5 * np.abs(x1 * y2 - x2 * y1)


def _area_quantile(values, areas, fraction):
    """The value of ``values`` (one per element) below which lie the values of a ``fraction`` of the area."""
    by_value = np.argsort(values)
    k = np.searchsorted(np.cumsum(areas[by_value]), fraction * areas.sum())
    return float(values[by_value][min(k, len(values) - 1)])


def _round_scale(scale):
    """The largest number 1, 2 or 5 times a power of ten not above ``scale`` (> 0): a magnification a reader
    takes in at a glance (displacement × 20, not × 26.1)."""
    power = 10.0 ** np.floor(np.log10(scale))
    return float(max(step for step in (1, 2, 5, 10) if step * power <= scale * (1 + 1e-12)) * power)


def plot_zone_marks(ax, sides):
    """The contact, stick and slip zones of ``sides`` ({side: ``ContactSide`` of :mod:`ngdgfric.forces`}) drawn
    along the contact sides in the styles of ``ZONE_STYLE``, one legend entry per zone present."""
    for name, style in ZONE_STYLE.items():
        pieces = [piece for side in sides.values() for piece in getattr(side, name).pieces]
        for k, piece in enumerate(pieces):
            ax.plot(piece[:, 0], piece[:, 1], solid_capstyle="butt", label=None if k else f"{name} zone", **style)


def write_deformed_png(path, sol, scale=None, sides=None):
    """Write the PNG of ``ngdgfric solve``: the deformed body of ``sol``.

    :func:`~ngdgfric.output.plot_deformed` on a figure of its own, written atomically.

    Parameters
    ----------
    path : str or pathlib.Path
        The PNG file to write.
    sol : Solution
        A solution of :func:`ngdgfric.solve` (:class:`ngdgfric.Solution`).
    scale : float or None, optional
        The displacement's magnification.  Default ``None``: as in :func:`~ngdgfric.output.plot_deformed`.
    sides : dict or None, optional
        The contact sides of ``sol``, as in :func:`~ngdgfric.output.plot_deformed`.  Default ``None``: computed.
    """
    fig = figure(6, 5)
    plot_deformed(fig.add_subplot(), sol, scale, sides)
    write_png(fig, path, dpi=130)


def estimator_curve(records):
    r"""(:math:`N`, :math:`\eta_h`): the DOFs and the estimator of the levels of :func:`ngdgfric.adapt` (float
    arrays)."""
    return np.array([r["ndof"] for r in records], dtype=float), np.array([r["eta_h"] for r in records])


def plot_estimator(ax, curves, slope=None, **line):
    r"""Draw the estimator :math:`\eta_h` (Section 4) against the number of DOFs :math:`N` on log-log axes.

    The axes are labelled by ``log_ticks`` (this module) for the range of everything drawn (so that a
    curve over a fraction of a decade has readable labels); a later ``loglog`` call on the Axes resets them (draw
    further curves with ``ax.plot``).  The legend is left to the caller.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The Axes to draw into.
    curves : dict
        ``{label: records}``, the records being the levels of :func:`ngdgfric.adapt` (``Adaptation.levels``,
        each with ``"ndof"`` and ``"eta_h"``), drawn with the markers o, s, ^, v in turn.
    slope : tuple or None, optional
        ``(records, p)``: the optimal rate :math:`N^{-p/2}` of adaptive :math:`P_p` elements (Section 6) drawn
        through the first level of ``records``.  Default ``None``: no slope.
    **line
        Matplotlib line options for every curve, e.g. ``ms=3``.
    """
    for (label, records), marker in zip(curves.items(), "os^v", strict=False):
        ax.loglog(*estimator_curve(records), f"{marker}-", label=label, **line)
    if slope is not None:
        (ndof, eta_h), p = estimator_curve(slope[0]), slope[1]
        ax.loglog(ndof, eta_h[0] * (ndof / ndof[0]) ** (-p / 2), "k--", label=rf"$N^{{-{p}/2}}$")
    ax.set_xlabel("degrees of freedom $N$")
    ax.set_ylabel(r"$\eta_h$")
    ax.grid(True, which="both", alpha=0.3)
    (x0, x1), (y0, y1) = ax.dataLim.intervalx, ax.dataLim.intervaly
    log_ticks(ax.xaxis, x1 / x0)
    log_ticks(ax.yaxis, y1 / y0)


def log_ticks(axis, ratio):
    """Label the log ``axis`` of data spanning ``ratio`` (largest over smallest) at ticks far enough apart.

    Powers of ten over two decades and more; over fewer, 1, 2 and 5 times them (down to half a decade) or
    round numbers (``MaxNLocator``) as plain numbers, so that a short axis has at least two labels and none
    overlap.  The minor ticks are never labelled (matplotlib labels them on short axes, wide and overlapping).
    """
    from matplotlib.ticker import FuncFormatter, LogLocator, MaxNLocator, NullFormatter

    decades = np.log10(ratio) if ratio > 0 else 0.0
    if decades < 2:
        if decades >= 0.5:
            axis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
        else:
            axis.set_major_locator(MaxNLocator(nbins=4, steps=[1, 2, 2.5, 5, 10]))
        axis.set_major_formatter(FuncFormatter(_plain_number))
    axis.set_minor_formatter(NullFormatter())


def _plain_number(value, _position=None):
    """A tick label: ``value`` as ``%g`` writes it, its exponent (if any) as a power of ten (``tex_number``)."""
    text = tex_number(value)
    return f"${text}$" if "10^" in text else text


def tex_number(value):
    """``value`` as TeX (without the dollars): as ``%g`` writes it, an exponent as a power of ten (1e+06 as
    ``10^{6}``, 2.5e-07 as ``2.5 \\times 10^{-7}``)."""
    mantissa, _, exponent = f"{value:g}".partition("e")
    if not exponent:
        return mantissa
    power = f"10^{{{int(exponent)}}}"
    return power if mantissa == "1" else f"{mantissa} \\times {power}"


def plot_mesh(ax, mesh, title):
    """Draw the triangles of ``mesh``, titled ``title``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The Axes to draw into.
    mesh : ngsolve.Mesh
        The mesh, e.g. ``Solution.mesh`` of the last level of :func:`ngdgfric.adapt`.
    title : str
        The Axes' title.
    """
    points, triangles = mesh_arrays(mesh)[:2]
    ax.triplot(points[:, 0], points[:, 1], triangles, lw=0.3, color="k")
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)


def write_adaptive_png(path, title, label, records, mesh, slope=None):
    """The PNG of ``ngdgfric adaptive``: :func:`~ngdgfric.output.plot_estimator` of ``records`` (one curve, ``label``;
    ``slope`` as there) beside the last level's ``mesh``, under ``title``."""
    fig = figure(10, 4.5)
    ax, mesh_ax = fig.subplots(1, 2)
    plot_estimator(ax, {label: records}, slope, ms=3)
    ax.legend(fontsize=8)
    plot_mesh(mesh_ax, mesh, f"level {records[-1]['level']}: {mesh.ne} elements")
    fig.suptitle(title)
    write_png(fig, path, dpi=120)


def plot_contact(axes, sol):
    r"""Draw the contact quantities of ``sol`` at the Gauss points of :math:`\Gamma_C`, left to right, on four Axes.

    Top to bottom: the normal compliance law (1.8), :math:`-\sigma_n(u_h)` against
    :math:`c_n (u_{hn} - g_a)_+^{m_n}`; the friction law (1.9), :math:`\sigma_\tau(u_h)` and the discrete friction
    traction :math:`-c_\tau \lambda_\tau` against the bound :math:`\pm c_\tau`; the slip :math:`u_{h\tau}`; the
    zones of :mod:`ngdgfric.forces`: contact where :math:`u_{hn} > g_a`, slip where :math:`|\lambda_\tau| = 1`
    and :math:`u_{h\tau} \ne 0`, stick where friction acts otherwise.

    Parameters
    ----------
    axes : sequence of matplotlib.axes.Axes
        Four Axes, top to bottom, e.g. ``plt.subplots(4, 1, sharex=True)[1]``.
    sol : Solution
        A solution of :func:`ngdgfric.solve` (:class:`ngdgfric.Solution`).
    """
    state = contact_state(sol)
    zones = {name: np.zeros(len(state["x"]), dtype=bool) for name in ("contact", "slip", "stick")}
    for side in contact_sides(sol).values():
        for name, mask in (("contact", side.in_contact), ("slip", side.slipping), ("stick", side.sticking)):
            zones[name][side.points] = mask
    order = np.argsort(state["x"])
    s = {k: np.asarray(v)[order] for k, v in state.items()}
    zones = {name: mask[order] for name, mask in zones.items()}
    x = s["x"]
    axes[0].plot(x, -s["sigma_n"], ".-", label=r"$-\sigma_n(u_h)$")
    axes[0].plot(x, s["pressure"], ".-", label=r"$c_n\,(u_{hn} - g_a)_+^{m_n}$")
    axes[0].set_title("normal compliance (1.8)")
    axes[1].plot(x, s["sigma_tau"], ".-", label=r"$\sigma_\tau(u_h)$")
    axes[1].plot(x, -s["c_tau"] * s["lam_tau"], ".-", label=r"$-c_\tau \lambda_\tau$")
    axes[1].plot(x, s["c_tau"], "k--", lw=1, label=r"$\pm c_\tau$")
    axes[1].plot(x, -s["c_tau"], "k--", lw=1)
    axes[1].set_title("friction (1.9)")
    axes[2].plot(x, s["u_tau"], ".-", label=r"$u_{h\tau}$")
    axes[2].set_title("slip")
    for k, (name, mask) in enumerate(zones.items()):
        axes[3].plot(x[mask], np.full(mask.sum(), k), "s", ms=5, color=ZONE_STYLE[name]["color"])
    axes[3].set_yticks(range(len(zones)), list(zones))
    axes[3].set_ylim(-0.5, len(zones) - 0.5)
    axes[3].set_title("zones")
    axes[3].set_xlabel(r"$x$ on $\Gamma_C$")
    for ax in axes[:3]:  # the legends right of the Axes, off the curves
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8)


def _runs(cells, mask):
    """The intervals of arc length covered by the consecutive cells ``cells`` (m, 2) where ``mask`` holds."""
    runs = []
    for (a, b), inside in zip(cells, mask, strict=True):
        if not inside:
            continue
        if runs and runs[-1][1] == a:
            runs[-1][1] = b
        else:
            runs.append([a, b])
    return runs


def plot_zones(ax, sol, side, sides=None):
    r"""Draw one contact side along its arc length: the pressure, :math:`|\lambda_\tau|` and the zones.

    Along the side from its start, along :math:`t = (-n_y, n_x)`: the pressure :math:`c_n (u_{hn} - g_a)_+^{m_n}`
    of (1.8) and, on a second axis, :math:`|\lambda_\tau|` (Lemma 3.1; 1 where the friction traction reaches its
    bound (1.9)) at the Gauss points, over the stick (blue) and slip (red) zones shaded and the contact zone as
    a grey band on the axis (:mod:`ngdgfric.forces`, whose Gauss cells give the zones' ends).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The Axes to draw into.
    sol : Solution
        A solution of :func:`ngdgfric.solve` (:class:`ngdgfric.Solution`).
    side : str
        The name of a contact side of the problem, or of a side of a contact pair.
    sides : dict or None, optional
        The contact sides of ``sol`` and the sides of its pairs (``all_sides`` of
        :mod:`ngdgfric.contact.pair_zones`), to share them between plots.  Default ``None``: computed.

    Returns
    -------
    matplotlib.axes.Axes
        The second Axes, of :math:`|\lambda_\tau|`.
    """
    c = (all_sides(sol) if sides is None else sides)[side]
    for name, mask in (("stick", c.sticking), ("slip", c.slipping)):
        for k, (a, b) in enumerate(_runs(c.cells, mask)):
            ax.axvspan(a, b, color=ZONE_STYLE[name]["color"], alpha=0.15, lw=0, label=None if k else f"{name} zone")
    for k, (a, b) in enumerate(_runs(c.cells, c.in_contact)):
        ax.plot([a, b], [0, 0], solid_capstyle="butt", label=None if k else "contact zone", **ZONE_STYLE["contact"])
    ax.plot(c.arc, c.pressure, "k.-", ms=3, lw=1,
            label=r"$f_n / \omega$" if c.partner else r"$c_n\,(u_{hn} - g_a)_+^{m_n}$")
    ax.set_xlim(0, c.length)
    x0, y0 = np.round(c.cell_ends[0, 0], 12) + 0.0  # no -0 or 1e-16 for a vertex on an axis
    ax.set_xlabel(f"arc length along {side} from ({x0:.3g}, {y0:.3g})")
    ax.set_ylabel("pressure")
    twin = ax.twinx()
    twin.plot(c.arc, np.abs(c.lam_tau), ".-", color="tab:purple", ms=3, lw=1,
              label=r"$|\lambda_\tau|$")
    twin.set_ylim(0, 1.05)
    twin.set_ylabel(r"$|\lambda_\tau|$", color="tab:purple")
    lines = ax.get_legend_handles_labels()
    more = twin.get_legend_handles_labels()
    ax.legend(lines[0] + more[0], lines[1] + more[1], fontsize=7, loc="best")
    paired = f" (pair with {c.partner})" if c.partner else ""
    ax.set_title(f"{side}{paired}: normal {c.normal:.4g}, tangential {c.tangential:.4g}", fontsize=9)
    return twin


def write_contact_png(path, sol, sides=None):
    """Write the contact PNG of ``ngdgfric solve`` and ``adaptive``: every contact side of ``sol``.

    :func:`~ngdgfric.output.plot_zones` of every contact side and of both sides of every contact pair, one above
    the other, written atomically.

    Parameters
    ----------
    path : str or pathlib.Path
        The PNG file to write.
    sol : Solution
        A solution of :func:`ngdgfric.solve` (:class:`ngdgfric.Solution`).
    sides : dict or None, optional
        The contact sides of ``sol``, as in :func:`~ngdgfric.output.plot_zones`.  Default ``None``: computed.
    """
    sides = all_sides(sol) if sides is None else sides
    fig = figure(7, 0.6 + 2.6 * len(sides))
    for ax, side in zip(fig.subplots(len(sides), 1, squeeze=False)[:, 0], sides, strict=True):
        plot_zones(ax, sol, side, sides)
    fig.suptitle(f"{sol.problem.name}: {sol.method} P{sol.max_order}, contact zones", fontsize=10)
    write_png(fig, path, dpi=110)
