"""Every #include of another aar package's header is declared in the including package's
package.xml with the kind of dependency its place needs (scripts/lint):
  include/ (public headers): <depend>, or <build_depend> with <build_export_depend>: whoever
      includes the header needs the other package's headers too;
  src/, tools/, fuzz/ and the rest: <depend> or <build_depend>;
  test/: <depend>, <build_depend> or <test_depend>.
Prints one line per undeclared include; exit status 1 when there is one."""
import glob
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"](aar_[a-z_]+)/', re.M)
DEPEND = re.compile(r"<(depend|build_depend|build_export_depend|exec_depend|test_depend)>"
                    r"(aar_[a-z_]+)</")


def declared(package_xml):
    kinds = {}
    with open(package_xml) as f:
        for kind, dep in DEPEND.findall(f.read()):
            kinds.setdefault(dep, set()).add(kind)
    return kinds


def needed(path):
    """The dependency kinds that satisfy an include from `path` (inside its package)."""
    top = path.split(os.sep)[0]
    if top == "include":
        return [{"depend"}, {"build_depend", "build_export_depend"}]
    if top == "test":
        return [{"depend"}, {"build_depend"}, {"test_depend"}]
    return [{"depend"}, {"build_depend"}]


def problems(root):
    found = []
    for package_xml in sorted(glob.glob(os.path.join(root, "src", "*", "package.xml"))):
        package_dir = os.path.dirname(package_xml)
        package = os.path.basename(package_dir)
        kinds = declared(package_xml)
        for source in sorted(glob.glob(os.path.join(package_dir, "**", "*.[ch]*"), recursive=True)):
            if not re.search(r"\.(h|hpp|cpp|cc)$", source):
                continue
            relative = os.path.relpath(source, package_dir)
            with open(source, errors="replace") as f:
                included = set(INCLUDE.findall(f.read()))
            for other in sorted(included - {package}):
                have = kinds.get(other, set())
                if not any(need <= have for need in needed(relative)):
                    what = " or ".join("+".join(sorted(n)) for n in needed(relative))
                    found.append(f"src/{package}/{relative} includes {other}/..., but "
                                 f"package.xml declares {sorted(have) or 'nothing'} for it "
                                 f"(needs {what})")
    return found


if __name__ == "__main__":
    out = problems(sys.argv[1] if len(sys.argv) > 1 else ".")
    print("\n".join(out))
    sys.exit(1 if out else 0)
