#!/usr/bin/python3
"""Every chart under docs/ shows each legend entry as its line is drawn: a swatch is dashed where
the series it names is dashed, solid where it is solid (a chart committed from an older renderer
would say otherwise). Usage: check_chart_legends.py DOCS_DIR"""
import glob
import os
import re
import sys


def main():
    charts = sorted(glob.glob(os.path.join(sys.argv[1], "*.svg")))
    failures = []
    for path in charts:
        text = open(path, encoding="utf-8").read()
        # (colour, dashed) of every drawn line, and of every legend swatch.
        drawn = {(m.group(1), "stroke-dasharray" in m.group(0))
                 for m in re.finditer(r"<polyline[^>]*stroke='([^']+)'[^>]*>", text)}
        # Points (a scatter) are solid marks: a solid swatch names them.
        drawn |= {(m.group(1), False) for m in re.finditer(r"<circle[^>]*fill='([^']+)'", text)}
        swatches = [(m.group(1), "stroke-dasharray" in m.group(0))
                    for m in re.finditer(r"<line[^>]*stroke='([^']+)' stroke-width='3'[^>]*>", text)]
        for colour, dashed in swatches:
            if (colour, dashed) not in drawn:
                failures.append(f"{os.path.basename(path)}: the {'dashed' if dashed else 'solid'} "
                                f"legend swatch in {colour} names no line drawn so")
    for failure in failures:
        print(failure)
    print(f"{len(charts)} charts, {len(failures)} legend swatches unlike their lines")
    return 1 if failures or not charts else 0


if __name__ == "__main__":
    sys.exit(main())
