"""The one style table of every figure (dbtools/plots/): each series of a figure gets its own colour AND its own marker,
so that no two series of a figure look alike (in colour or in grey print).

A series name that several figures share (an ordering, a backend, a frames configuration, a Table 2-1 build) keeps
one style in all of them: KINDS lists each kind's names in a fixed order, and the k-th name of a kind gets the k-th
colour and the k-th marker. A name no kind lists (a BLAS core, a scaling series) gets the next style that no other
series of the figure uses.

  from .styles import styles
  st = styles("ordering", ["default", "amd", "qamd"])   # name -> {"color": ..., "marker": ...}
  ax.plot(x, y, label=name, **st[name])
"""

# tab10, then ten more hues that read apart from it and from each other on white.
COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
           "#17becf", "#000000", "#800000", "#000075", "#808000", "#469990", "#f032e6", "#7cb518", "#e6b800",
           "#5e3c99", "#ff6f91")
# The filled markers first (a hollow marker means "predicted, not measured" in the Table 2-1 plots, whose kind has
# fewer names than there are filled markers), then line-only ones.
MARKERS = ("o", "s", "^", "v", "D", "P", "X", "<", ">", "p", "h", "*", "d", "H", "8", "+", "x", "1", "2", "3")
STYLES = tuple(zip(COLOURS, MARKERS))

KINDS = {
    "ordering": ["default", "amd", "metis", "nesdis", "natural", "colamd", "amf", "qamd", "pord", "scotch",
                 "ptscotch", "vertex-metis"],
    "backend": ["cholmod_supernodal", "multifrontal", "multifrontal_mixed", "multifrontal_refined", "mumps",
                "mumps_refined", "cholmod_simplicial_ldlt", "dense_llt", "lapack_potrf", "dense_ldlt_bk", "dense_lu",
                "eigen_simplicial_llt", "eigen_simplicial_ldlt", "eigen_sparse_lu", "umfpack", "cg_jacobi",
                "cg_ichol", "spqr"],
    "config": ["lap", "tf", "tf-normalized", "lri-first-gram_schmidt", "lri-random-gram_schmidt",
               "lri-height_angle-gram_schmidt", "lri-curvature-gram_schmidt", "lri-first-polar",
               "lri-uncoordinated"],
    "table_2_1": ["tf structured", "tf naive", "tf dense", "lap structured", "lap naive", "lap dense",
                  "thesis tf before", "thesis tf after"],
}


def styles(kind, names):
    """name -> {"color", "marker"} for the series of one figure, all distinct. kind: a key of KINDS (its names keep
    their fixed style) or None (every name by its position)."""
    fixed = KINDS.get(kind, []) if kind else []
    out, used = {}, set()
    for n in names:
        if n in fixed and n not in out:
            i = fixed.index(n)
            out[n] = i
            used.add(i)
    free = (i for i in range(len(STYLES)) if i not in used)
    for n in names:
        if n not in out:
            i = next(free, None)
            if i is None:
                raise ValueError(f"styles: more than {len(STYLES)} series in one figure")
            out[n] = i
    return {n: {"color": STYLES[i][0], "marker": STYLES[i][1]} for n, i in out.items()}


def check():
    """The style table's own promise: no two styles share a colour or a marker, and every kind fits in the table with
    its names listed once. Returns a list of problems (empty: sound)."""
    problems = []
    for what, items in (("colour", COLOURS), ("marker", MARKERS)):
        if len(set(items)) != len(items):
            problems.append(f"a {what} appears twice")
    if len(COLOURS) != len(MARKERS):
        problems.append(f"{len(COLOURS)} colours but {len(MARKERS)} markers")
    for kind, names in KINDS.items():
        if len(set(names)) != len(names):
            problems.append(f"kind {kind}: a name listed twice")
        if len(names) > len(STYLES):
            problems.append(f"kind {kind}: {len(names)} names, {len(STYLES)} styles")
    return problems

