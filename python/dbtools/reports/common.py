"""What every report needs: reading the drivers' CSVs, formatting numbers, writing a file atomically.

Standard library only: the reports run with any python3 (the report step, dbtools.report, also draws the figures
and so needs Debian's /usr/bin/python3 with numpy and matplotlib).
"""
import csv
import math
import os
import statistics
import tempfile

MIB = 1024.0 * 1024.0
NAN = float("nan")
FIGURES = "figures"  # the figures' folder under the results directory; reports cite them as figures/NAME.png


def figures_dir(results):
    """Where the figures of a results directory go (and where its reports look for them): RESULTS/figures."""
    return os.path.join(results, FIGURES)


def cite_figure(results, name, made_by):
    """"`figures/NAME`", and " (missing: MADE_BY)" after it when RESULTS/figures/NAME is not there: the report step
    draws the figures first, so a missing one is a figure its module did not draw."""
    rel = f"{FIGURES}/{name}"
    return f"`{rel}`" if os.path.exists(os.path.join(figures_dir(results), name)) else f"`{rel}` (missing: {made_by})"


def read_rows(path):
    """Every row of a CSV as a dict; [] when the file does not exist."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    """A CSV value as a float (NaN for "", "n/a", "nan" or anything else that is not a number)."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return NAN


def isnan(x):
    return x is None or (isinstance(x, float) and math.isnan(x))


def settings(path):
    """The setting -> value rows of a driver's *_settings.csv ({} when absent)."""
    return {r["setting"]: r["value"] for r in read_rows(path)}


def provenance(rows):
    """The provenance columns of a CSV's first row ({} for no rows)."""
    keys = ("git_sha", "blas", "blas_core", "blas_coretype_env", "blas_threads", "build_threads", "hardware_threads",
            "cpu", "compiler", "timestamp")
    return {k: rows[0].get(k, "") for k in keys} if rows else {}


class Cell:
    """One cell of a long CSV (one row per measure): its key columns, status, message and measures."""

    def __init__(self, row, key_columns):
        self.key = {k: row.get(k, "") for k in key_columns}
        self.status = row.get("status", "ok")
        self.message = row.get("message", "")
        self.row = row
        self.values = {}

    def __getattr__(self, name):
        if name in ("key", "status", "message", "row", "values"):
            raise AttributeError(name)
        return self.key[name]

    def ok(self):
        return self.status == "ok"

    def get(self, measure):
        """The measure's value, NaN when absent or empty."""
        return self.values.get(measure, NAN)


def cells(rows, key_columns):
    """Groups a long CSV into Cells by `key_columns`, in file order."""
    out, index = [], {}
    for r in rows:
        k = tuple(r.get(c, "") for c in key_columns)
        if k not in index:
            index[k] = len(out)
            out.append(Cell(r, key_columns))
        c = out[index[k]]
        c.values[r["measure"]] = number(r.get("value"))
    return out


def median(values):
    v = [x for x in values if not isnan(x)]
    return statistics.median(v) if v else NAN


def geomean(values):
    v = [x for x in values if not isnan(x) and x > 0 and math.isfinite(x)]
    return math.exp(sum(math.log(x) for x in v) / len(v)) if v else NAN


def minmax(values):
    v = [x for x in values if not isnan(x) and math.isfinite(x)]
    return (min(v), max(v)) if v else (NAN, NAN)


def fmt(x, spec="{:.3g}", missing="-"):
    """A number with a format spec, `missing` for NaN."""
    return missing if isnan(x) else spec.format(x)


# A timing's spread over its repeats (harness/cell.h spread_name): NAME_s is the median, NAME_min_s and NAME_max_s the
# least and largest repeat, NAME_reps their count. Repeats further apart than SPREAD_FLAG (max > SPREAD_FLAG x min,
# harness/stats.h kSpreadFlagRatio) are flagged with FLAG wherever the timing is shown.
SPREAD_FLAG = 2.0
FLAG = "**(!)**"
SPREAD_NOTE = (f"{FLAG}: this timing's repeats are more than {SPREAD_FLAG:g}x apart (largest / least): a thread waited "
               "on a descheduled worker or the machine was busy, so its median may be unreliable. A spread is "
               "written (least - largest, n = repeats); from three repeats on it leaves out the first, which warms up "
               "(a drag's first frame also stores the rest pose's forward substitution).")


def spread_name(measure, stat):
    """"frame_s", "min" -> "frame_min_s"; "reps" -> "frame_reps"."""
    base = measure[:-2] if measure.endswith("_s") else measure
    return f"{base}_reps" if stat == "reps" else f"{base}_{stat}_s"


def spread(get, measure):
    """(least, largest, repeats) of a timed measure; `get` maps a measure name to its value (NaN when absent)."""
    return get(spread_name(measure, "min")), get(spread_name(measure, "max")), get(spread_name(measure, "reps"))


def flagged(get, measure):
    """Whether the measure's repeats disagree by more than SPREAD_FLAG."""
    lo, hi, n = spread(get, measure)
    return not isnan(n) and n > 1 and not isnan(hi) and hi > 0 and not lo * SPREAD_FLAG >= hi


def mark(get, measure):
    """" (!)" for a flagged timing, "" otherwise."""
    return " " + FLAG if flagged(get, measure) else ""


def spread_text(get, measure, form=lambda x: f"{x:.3g}"):
    """"(0.29 - 3.97, n=5) (!)": the measure's spread with its flag; "" when the CSV has none."""
    lo, hi, n = spread(get, measure)
    if isnan(lo) or isnan(hi) or isnan(n):
        return ""
    return f"({form(lo)} - {form(hi)}, n={n:.0f}){mark(get, measure)}"


def repeated_spread(get, measure, form=lambda x: f"{x:.3g}"):
    """" (0.29 - 3.97, n=5)" after a timing that is a median of several repetitions; "" for one run or none."""
    n = spread(get, measure)[2]
    return " " + spread_text(get, measure, form) if not isnan(n) and n > 1 and not isnan(get(measure)) else ""


def count_flagged(items, measures):
    """How many (item, measure) pairs of `items` (getters) are flagged."""
    return sum(flagged(get, m) for get in items for m in measures)


def write_atomically(path, text):
    """Writes `text` to a temporary file beside `path`, then renames it into place: no partial report. The report
    gets the mode a newly created file gets (0666 less the umask, as the drivers' CSVs), not mkstemp's 0600."""
    d = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=os.path.basename(path) + ".", suffix=".tmp", dir=d)
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.fchmod(fd, 0o666 & ~umask)
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
