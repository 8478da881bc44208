#!/usr/bin/env python3
"""Write test/data/jazzy_rosdep_keys.txt from a checkout of ros/rosdistro (issue 24, point 3).

Usage: python tools/rosdep_keys.py ROSDISTRO_CHECKOUT [--commit HASH]

Keeps the names only: the rosdep keys of rosdep/base.yaml and rosdep/python.yaml that resolve
on Jazzy's Ubuntu (noble), and the Jazzy packages (jazzy/distribution.yaml) that package.xml
names. test/test_package_xml.py checks every dependency of package.xml against that list.
"""
import argparse
import re
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "test" / "data" / "jazzy_rosdep_keys.txt"
PLATFORM, CODENAME = "ubuntu", "noble"
INSTALLERS = {"apt", "pip", "source"}


def resolves(rule):
    """Does a rosdep rule give something to install (or nothing needed) on Ubuntu noble?"""
    if not isinstance(rule, dict) or rule.get(PLATFORM) is None:
        return False
    entry = rule[PLATFORM]
    if isinstance(entry, (list, str)) or INSTALLERS & set(entry):
        return True
    return entry.get(CODENAME, entry.get("*")) is not None


def jazzy_packages(distribution):
    names = set()
    for name, repo in distribution["repositories"].items():
        if repo.get("release"):
            names.update(repo["release"].get("packages", [name]))
    return names


def package_xml_names(path):
    return set(re.findall(r"<\w*depend>([^<]+)</\w*depend>", path.read_text()))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rosdistro", type=Path)
    parser.add_argument("--commit", default="", help="the checkout's commit, for the header")
    args = parser.parse_args(argv)
    keys = set()
    for name in ("base.yaml", "python.yaml"):
        rules = yaml.safe_load((args.rosdistro / "rosdep" / name).read_text())
        keys.update(k for k, rule in rules.items() if resolves(rule))
    distribution = yaml.safe_load((args.rosdistro / "jazzy" / "distribution.yaml").read_text())
    ros = jazzy_packages(distribution) & package_xml_names(ROOT / "package.xml")
    header = (f"# rosdep keys resolving on {PLATFORM} {CODENAME} (rosdep/base.yaml, python.yaml)"
              f" and the Jazzy packages package.xml names (jazzy/distribution.yaml);\n"
              f"# ros/rosdistro {args.commit or 'checkout'}; written by tools/rosdep_keys.py\n")
    OUT.write_text(header + "".join(f"{k}\n" for k in sorted(keys | ros)))
    print(f"{OUT}: {len(keys)} rosdep keys, {len(ros)} Jazzy packages", file=sys.stderr)


if __name__ == "__main__":
    main()
