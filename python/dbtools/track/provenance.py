"""Whether a baseline may gate a run: the same suite definition (else stale) on the same machine (else foreign).

stale    the baseline was measured by another definition of the suite, so its values are not this suite's:
         its `suite` (the definition hash or version a record carries: bench_phases' benchmark list and version)
         differs from the run's; it holds cells the current suite no longer defines; a cell both ran is defined
         otherwise (its spec: mesh, method, build, backend, frames, ... ; keys the run's own --override rules set
         are the change under test, not staleness); a measure has another class; or a cell both ran no longer
         reports one of the baseline's measures. Exit 3 (STALE_EXIT) unless --allow-stale.
foreign  recorded on another machine, BLAS core, thread count or build type (its machine id or build type
         differs): times do not transfer. Exit 4 (FOREIGN_EXIT) unless --allow-foreign, which gates its
         deterministic measures only.
The message names the baseline (commit, date, machine, file) and every reason.
"""
from dataclasses import dataclass

STALE_EXIT = 3
FOREIGN_EXIT = 4
MACHINE = (("machine_cpu", "CPU"), ("machine_blas_core", "BLAS core"), ("machine_cores", "cores"),
           ("machine_ram_gib", "RAM (GiB)"), ("machine_threads", "threads (BLAS/build)"), ("build_type", "build"))
SHOWN = 8  # reasons listed in a message; the rest counted


class Refused(Exception):
    """The baseline may not gate the run: stale or foreign (exit_code 3 or 4)."""

    def __init__(self, kind, base, reasons):
        self.kind, self.reasons = kind, reasons
        self.exit_code = STALE_EXIT if kind == "stale" else FOREIGN_EXIT
        super().__init__(refusal_message(kind, base, reasons))


def describe_machine(meta):
    parts = [f"{label} {meta[k]}" for k, label in MACHINE if meta.get(k)]
    return f"machine {meta.get('machine_id') or '?'}" + (f" ({', '.join(parts)})" if parts else "")


def refusal_message(kind, base, reasons):
    m = base.meta
    head = (f"the baseline {base.path} (commit {m.get('git_sha') or m.get('commit', '')[:12]}, {m.get('date')}, "
            f"{describe_machine(m)}) is {kind}: ")
    listed = "; ".join(reasons[:SHOWN]) + (f"; and {len(reasons) - SHOWN} more" if len(reasons) > SHOWN else "")
    fix = ("record a baseline of the current suite (./run track --save-reference, or ./run track bench "
           "--update-baseline), or compare anyway with --allow-stale" if kind == "stale" else
           "record a baseline on this machine (./run track --save-reference, or ./run track bench "
           "--update-baseline), or gate its deterministic measures only with --allow-foreign")
    return head + listed + ": " + fix


def spec_items(spec):
    return dict(t.split("=", 1) for t in spec.split() if "=" in t)


def override_keys(overrides):
    """The keys that a run's rules 'match: key=value ...; ...' set."""
    keys = set()
    for rule in overrides.split(";"):
        keys |= set(spec_items(rule.partition(":")[2]))
    return keys


def _names(cells):
    cells = sorted(cells)
    return ", ".join(cells[:3]) + (f" (+{len(cells) - 3} more)" if len(cells) > 3 else "")


def stale_reasons(base, now, suite_cells=None):
    """Why `base` is not a record of the suite `now` ran (empty: it is). `suite_cells`: the cells the current suite
    defines, when the caller knows them."""
    out = []
    bs, ns = base.meta.get("suite", ""), now.meta.get("suite", "")
    if (bs or ns) and bs != ns:
        out.append(f"suite definition '{bs or 'not recorded'}' in the baseline, '{ns or 'not recorded'}' now")
    if suite_cells is not None and base.cells - set(suite_cells):
        gone = base.cells - set(suite_cells)
        out.append(f"{len(gone)} cell(s) the suite no longer defines: {_names(gone)}")
    excused = override_keys(now.meta.get("overrides", ""))
    ran = (base.cells & now.cells) - set(now.failed) - set(base.failed)
    for cell in sorted(ran):
        b, n = spec_items(base.specs.get(cell, "")), spec_items(now.specs.get(cell, ""))
        for k in sorted((set(b) | set(n)) - excused):
            if b.get(k) != n.get(k):
                out.append(f"{cell}: {k}={b.get(k, '(unset)')} in the baseline, {n.get(k, '(unset)')} now")
    for key in sorted(set(base.classes) & set(now.classes)):
        if base.classes[key][0] != now.classes[key][0]:
            out.append(f"{key[0]} {key[1]}: class {base.classes[key][0]} in the baseline, {now.classes[key][0]} now")
    gone = sorted(k for k in base.values if k[0] in ran and k not in now.values)
    for cell, measure in gone:
        out.append(f"{cell}: {measure} no longer measured")
    return out


def foreign_reasons(base, now):
    """How the machine or build of `base` differs from that of `now` (empty: the same)."""
    b, n = base.meta, now.meta
    out = [f"{label} {b.get(k) or '(not recorded)'} in the baseline, {n.get(k) or '(not recorded)'} now"
           for k, label in MACHINE if b.get(k) != n.get(k) and (b.get(k) or n.get(k))]
    if b.get("machine_id") != n.get("machine_id") and not out:
        out.append(f"machine id {b.get('machine_id')} in the baseline, {n.get('machine_id')} now")
    return out


@dataclass
class Verdict:
    """What the checks allowed: whether times are comparable (same machine) and the notes for the report."""
    same_machine: bool
    notes: list


def check(base, now, suite_cells=None, allow_stale=False, allow_foreign=False):
    """Refused (stale first) unless allowed; else the Verdict."""
    stale, foreign = stale_reasons(base, now, suite_cells), foreign_reasons(base, now)
    if stale and not allow_stale:
        raise Refused("stale", base, stale)
    if foreign and not allow_foreign:
        raise Refused("foreign", base, foreign)
    notes = []
    if stale:
        notes.append(f"stale baseline compared anyway (--allow-stale): {'; '.join(stale[:SHOWN])}")
    if foreign:
        notes.append(f"foreign baseline (--allow-foreign): deterministic measures only: {'; '.join(foreign)}")
    return Verdict(not foreign, notes)
