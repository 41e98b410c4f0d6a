#!/usr/bin/env python3
"""Turns hal/sim/plant_params.json into a C++ header of constants (one per number, with its
source as a comment). Usage: gen_plant_params.py INPUT.json OUTPUT.h"""
import json
import re
import sys


def camel(text):
    return "".join(part[:1].upper() + part[1:] for part in re.split(r"[_\W]+", text) if part)


def main():
    source, output = sys.argv[1], sys.argv[2]
    data = json.load(open(source, encoding="utf-8"))
    lines = ["// Generated from hal/sim/plant_params.json by gen_plant_params.py; do not edit.",
             "#pragma once", "", "namespace palpa::sim::params {", ""]
    for section, entries in data.items():
        if section == "comment":
            continue
        for key, entry in entries.items():
            if set(entry) != {"value", "source"}:
                raise SystemExit(f"{source}: {section}.{key} needs exactly value and source")
            value = entry["value"]
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                raise SystemExit(f"{source}: {section}.{key} is not a number")
            lines.append(f"// {entry['source']}")
            lines.append(f"inline constexpr float k{camel(section)}{camel(key)} = {float(value)!r}f;")
    lines += ["", "}  // namespace palpa::sim::params", ""]
    with open(output, "w", encoding="utf-8") as out:
        out.write("\n".join(lines))


if __name__ == "__main__":
    main()
