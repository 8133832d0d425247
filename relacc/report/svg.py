"""Self-contained pictures for the report: matplotlib figures and formulas as SVG data URIs.

Every picture is an SVG with glyphs drawn as paths (no font, no network) and
no timestamp, embedded as ``data:image/svg+xml;base64,...`` so that ids of
different pictures never collide.
"""

from __future__ import annotations

import base64
import hashlib
import io
import itertools
import re

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

plt.rcParams.update(
    {
        "svg.fonttype": "path",
        "svg.hashsalt": "relacc",
        "font.size": 9,
        "axes.grid": True,
        "grid.alpha": 0.3,
    }
)


def data_uri(svg: bytes) -> str:
    """``data:image/svg+xml;base64,...`` of an SVG document."""
    return "data:image/svg+xml;base64," + base64.b64encode(svg).decode("ascii")


_FIGURES = itertools.count()


def inline(fig) -> str:
    """A matplotlib figure as inline SVG markup for an HTML page: text as ``<text>`` elements (a browser can measure
    them; the page names its font), no XML prolog, sized by its ``viewBox`` to the width of its container; the figure
    is closed; matplotlib's RDF metadata is left out. Names in it come from a model file: matplotlib escapes ``<``,
    ``>`` and ``&`` in text."""
    buf = io.StringIO()
    with plt.rc_context({"svg.fonttype": "none"}):
        fig.savefig(buf, format="svg", bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)
    svg = buf.getvalue()
    svg = svg[svg.index("<svg"):]
    svg = re.sub(r"<metadata>.*?</metadata>\s*", "", svg, count=1, flags=re.S)  # RDF naming outside addresses
    # ids unique in the page (several figures in one document): each prefixed by a digest of the figure and its
    # number in this process (two identical figures on one page stay apart)
    prefix = f"f{next(_FIGURES)}" + hashlib.sha1(svg.encode()).hexdigest()[:8] + "-"
    svg = re.sub(r'\bid="([^"]+)"', lambda m: f'id="{prefix}{m.group(1)}"', svg)
    svg = re.sub(r'url\(#([^)]+)\)', lambda m: f"url(#{prefix}{m.group(1)})", svg)
    svg = re.sub(r'href="#([^"]+)"', lambda m: f'href="#{prefix}{m.group(1)}"', svg)
    return re.sub(r'<svg([^>]*?) width="[^"]*" height="[^"]*"', r'<svg\1 class="drawing" width="100%"', svg, count=1)


def figure(fig) -> str:
    """A matplotlib figure as an SVG data URI; the figure is closed."""
    buf = io.BytesIO()
    fig.savefig(buf, format="svg", bbox_inches="tight", metadata={"Date": None})
    plt.close(fig)
    return data_uri(buf.getvalue())


def split_tex(tex: str, width: int = 160) -> list[str]:
    """Break a long formula at top-level ``" + "``, ``" - "`` and ``",\\;"`` into lines of about ``width`` characters.

    Only breaks outside every ``{}``, ``()`` and ``[]`` group; continuation
    lines start with ``\\quad``.
    """
    pieces, depth, start, i = [], 0, 0, 0
    while i < len(tex):
        ch = tex[i]
        if ch in "{([":
            depth += 1
        elif ch in "})]":
            depth -= 1
        elif depth == 0 and (tex.startswith(" + ", i) or tex.startswith(" - ", i)):
            pieces.append(tex[start:i])
            start, i = i, i + 3
            continue
        elif depth == 0 and tex.startswith(r",\;", i):
            pieces.append(tex[start : i + 3])
            start = i = i + 3
            continue
        i += 1
    pieces.append(tex[start:])
    lines, current = [], ""
    for piece in pieces:
        if current and len(current) + len(piece) > width:
            lines.append(current)
            current = piece
        else:
            current += piece
    lines.append(current)
    return [lines[0]] + [r"\quad " + line.strip() for line in lines[1:]]


def formula_lines(tex: str, fontsize: int = 12) -> list[str]:
    """A formula as SVG data URIs, one per line of :func:`split_tex`."""
    return [formula(line, fontsize) for line in split_tex(tex)]


def legend_below(fig, ax, ncol: int, offset: float = -0.15, fontsize: int = 7) -> None:
    """One legend for a row of panels, from ``ax``'s labelled lines, centred below the figure."""
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=fontsize, loc="lower center", ncol=ncol, bbox_to_anchor=(0.5, offset))


def log_axes(ax, title: str, xlabel: str) -> None:
    """Log-log axes with a small title and an x label."""
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel(xlabel)


def formula(tex: str, fontsize: int = 11) -> str:
    """A LaTeX formula (matplotlib mathtext subset) as an SVG data URI, drawn as ``matplotlib.mathtext.math_to_image``
    draws it but with no date in its metadata (``math_to_image`` has no way to leave it out: every formula of a page
    carried the time it was drawn)."""
    from matplotlib.figure import Figure
    from matplotlib.mathtext import MathTextParser

    buf = io.BytesIO()
    prop = matplotlib.font_manager.FontProperties(size=fontsize)
    text = f"${tex}$"
    width, height, depth, _, _ = MathTextParser("path").parse(text, dpi=72, prop=prop)
    fig = Figure(figsize=(width / 72.0, height / 72.0))
    fig.text(0, depth / height, text, fontproperties=prop)
    fig.savefig(buf, dpi=72, format="svg", metadata={"Date": None})
    return data_uri(buf.getvalue())
