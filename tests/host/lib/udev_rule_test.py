#!/usr/bin/python3
"""The udev rule against the devices a lab has: it opens palpa boards to the logged-in user, and
nothing else that shares the pid.codes test id 1209:0001 with them.

Each rule line is read as udev reads it (KEY==VALUE matches with shell-style globs, ATTR on the
device itself, ATTRS on the device or one parent, all ATTRS of a rule on the same one) and matched
against sysfs-like device descriptions: a USB device node and the hidraw node below it.
"""
import fnmatch
import re
import sys

RULE = re.compile(r'([A-Z_]+)(\{([^}]*)\})?\s*(==|!=|\+=|=|:=)\s*"([^"]*)"')


def parse(path):
    rules = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                rules.append([m.groups() for m in RULE.finditer(line)])
    return rules


def matches(rule, device):
    """device: {"subsystem", "kernel", "attrs"} with "parents": a list of attribute dicts."""
    parents_attrs = []
    for key, _, attr, op, value in rule:
        if op not in ("==", "!="):
            continue
        if key == "SUBSYSTEM":
            actual = [device["subsystem"]]
        elif key == "KERNEL":
            actual = [device["kernel"]]
        elif key == "ATTR":
            actual = [device["attrs"].get(attr)]
        elif key == "ATTRS":
            parents_attrs.append((attr, op, value))
            continue
        else:
            raise AssertionError("a key this test does not model: " + key)
        hit = any(a is not None and fnmatch.fnmatchcase(a, value) for a in actual)
        if hit != (op == "=="):
            return False
    if not parents_attrs:
        return True
    # All ATTRS keys of one rule must match on one device of the chain.
    for attrs in [device["attrs"]] + device["parents"]:
        if all((attrs.get(a) is not None and fnmatch.fnmatchcase(attrs[a], v)) == (op == "==")
               for a, op, v in parents_attrs):
            return True
    return False


def grants_access(rules, device):
    return any(matches(r, device) and any(k == "TAG" and v == "uaccess" for k, _, _, _, v in r)
               for r in rules)


def usb_and_hidraw(vendor, product, name):
    usb = {"idVendor": vendor, "idProduct": product, "product": name}
    return [
        {"subsystem": "usb", "kernel": "1-1", "attrs": usb, "parents": []},
        {"subsystem": "hidraw", "kernel": "hidraw3", "attrs": {}, "parents": [{}, usb]},
    ]


def main():
    rules = parse(sys.argv[1])
    failures = []
    for name in ("palpa actuator board", "palpa stm32f4"):
        for device in usb_and_hidraw("1209", "0001", name):
            if not grants_access(rules, device):
                failures.append("a palpa board (%s, %s) is not opened" % (name, device["kernel"]))
    for vendor, product, name in (("1209", "0001", "Generic test device"),
                                  ("1209", "0001", "USB-serial demo"),
                                  ("1209", "0002", "palpa actuator board")):
        for device in usb_and_hidraw(vendor, product, name):
            if grants_access(rules, device):
                failures.append("%s:%s '%s' (%s) is opened too" %
                                (vendor, product, name, device["kernel"]))
    for f in failures:
        print("udev rule: " + f)
    print("udev rule: %s" % ("ok" if not failures else "%d failures" % len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
