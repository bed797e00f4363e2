import argparse
import os
import sys

from . import __doc__ as doc, write


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m dbtools.site", description=doc.split("\n")[0])
    ap.add_argument("--results", default="results", help="the results directory (the site goes to RESULTS/site/)")
    a = ap.parse_args(argv)
    if not os.path.isdir(a.results):
        print(f"site: error: --results {a.results}: not a directory", file=sys.stderr)
        return 1
    write(a.results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
