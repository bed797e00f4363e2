"""The one way a figure draws a timing's spread: a marker at its value and a bar from its least to its largest
repetition (or round)."""


def spread_bars(ax, x, y, lo, hi, **style):
    """Markers (and a line, unless style says linestyle="none") at y, each with a bar from lo to hi."""
    return ax.errorbar(x, y, yerr=[[v - a for v, a in zip(y, lo)], [b - v for v, b in zip(y, hi)]],
                       capsize=style.pop("capsize", 2), **style)
