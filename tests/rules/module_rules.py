#!/usr/bin/env python3
"""The module rule of docs/architecture.md, checked: what each module may include and link.

docs/architecture.md's table "Modules and what they own" is the source of truth. For each
module folder (src/<module>/, cli/) its column "uses" names the modules and libraries it may
use. This script reads every #include of src/, include/dynpm/ and cli/, and every
target_link_libraries() of src/*/CMakeLists.txt and cli/CMakeLists.txt, and fails on each one
the table does not allow, naming the file, the line and the rule:

  - "x.h" (no folder) must be a header of the including file's own folder;
  - "dynpm/x.h" is the public header of the module that owns it: x.h named after a module
    (io.h → io), or named in that module's "owns" column (`text.h` → core);
  - "<module>/x.h" (an internal header of another module, include path src/) needs that
    module in "uses" — the CLI ("public API") may use public headers only;
  - <netcdf.h>, <zlib.h>, <zstd.h> need netCDF, zlib, zstd in "uses";
  - a header under include/dynpm/ follows the rule of the module that owns it;
  - nothing under src/ prints, exits or reads the environment (the table's last rule).

Usage: module_rules.py [REPO_ROOT]   (exit 0: every rule holds; 1: a list of violations)
"""
import pathlib
import re
import sys

MODULES = ["core", "io", "simplify", "progressive", "lod", "pipeline", "eval"]
# Made at build time, not in the source tree: the viewer's files embedded into the CLI.
GENERATED = {"cli": {"assets.h"}}
LIBRARIES = {"netcdf.h": "netCDF", "zlib.h": "zlib", "zstd.h": "zstd", "zstd_errors.h": "zstd"}
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
# What src/ must not do: print, exit, read the environment (std::snprintf into a buffer is fine;
# _exit() ends a forked reader child, not the process that called the library).
# `(?<!\w)exit(` also finds std::exit( and ::exit(.
FORBIDDEN = re.compile(r"std::cout|std::cerr|std::clog|\bprintf\s*\(|\bputs\s*\(|"
                       r"(?<!\w)exit\s*\(|\bgetenv\s*\(|fprintf\s*\(\s*(stdout|stderr)")


def read_table(root):
    """folder → (owns text, set of allowed modules, set of allowed libraries, public only)."""
    text = (root / "docs/architecture.md").read_text()
    section = text.split("## Modules and what they own", 1)
    if len(section) != 2:
        sys.exit("docs/architecture.md: no section 'Modules and what they own'")
    rules = {}
    for line in section[1].splitlines():
        if not line.startswith("|"):
            if rules:
                break
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 4 or not cells[0].startswith("`"):
            continue
        folder = cells[0].strip("`").rstrip("/")
        owns, uses = cells[2], cells[3]
        words = set(re.findall(r"[A-Za-z]+", uses))
        allowed = {m for m in MODULES if m in words}
        libraries = {lib for lib in LIBRARIES.values() if lib in words}
        public_only = "public API" in uses
        rules[folder] = (owns, allowed, libraries, public_only)
    return rules


def module_of_folder(path, root):
    rel = path.relative_to(root).as_posix()
    if rel.startswith("src/"):
        return "src/" + rel.split("/")[1]
    if rel.startswith("cli/"):
        return "cli"
    return None


def owner_of_public_header(name, rules):
    stem = name[:-2] if name.endswith(".h") else name
    if stem in MODULES:
        return "src/" + stem
    for folder, (owns, _, _, _) in rules.items():
        if folder.startswith("src/") and f"`{name}`" in owns:
            return folder
    return None


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    rules = read_table(root)
    problems = []
    for folder in [f"src/{m}" for m in MODULES] + ["cli"]:
        if folder not in rules:
            problems.append(f"docs/architecture.md: the table has no row for `{folder}/`")
    if problems:
        print("\n".join(problems))
        return 1

    def check_include(path, number, kind, name, folder):
        _, allowed, libraries, public_only = rules[folder]
        where = f"{path.relative_to(root)}:{number}"
        own = "src/" + folder.split("/")[1] if folder.startswith("src/") else folder
        if kind == "<":
            lib = LIBRARIES.get(name)
            if lib and lib not in libraries:
                problems.append(f"{where}: includes <{name}>, but {folder}/ may not use {lib} "
                                f"(docs/architecture.md: uses '{', '.join(sorted(libraries)) or 'no library'}')")
            return
        parts = [p for p in name.split("/") if p != ".."]
        if len(parts) == 1:
            if not (path.parent / name).exists() and name not in GENERATED.get(folder, ()):
                problems.append(f"{where}: includes \"{name}\", which is not in its own folder")
            return
        if parts[0] == "dynpm":
            owner = owner_of_public_header(parts[1], rules)
            if owner is None:
                problems.append(f"{where}: includes \"{name}\": no module's row in "
                                f"docs/architecture.md owns include/dynpm/{parts[1]}")
                return
            module = owner.split("/")[1]
            if owner != own and not public_only and module not in allowed:
                problems.append(f"{where}: {folder}/ includes \"{name}\" (module {module}), "
                                f"which docs/architecture.md does not let it use")
            return
        if parts[0] in MODULES:
            module = parts[0]
            if public_only:
                problems.append(f"{where}: {folder}/ uses the public API only, but includes the "
                                f"internal header \"{name}\" of src/{module}/")
            elif "src/" + module != own and module not in allowed:
                problems.append(f"{where}: {folder}/ includes \"{name}\" (internal to "
                                f"src/{module}/), which docs/architecture.md does not let it use")
            return
        # Generated headers (cli's embedded viewer assets) live in the build tree.
        if not (root / name).exists() and folder != "cli":
            problems.append(f"{where}: includes \"{name}\", which no module provides")

    def scan(path, folder):
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            m = INCLUDE.match(line)
            if m:
                check_include(path, number, m.group(1), m.group(2), folder)
            elif folder.startswith("src/") and FORBIDDEN.search(line.split("//", 1)[0]):
                problems.append(f"{path.relative_to(root)}:{number}: src/ must not print, exit "
                                f"or read the environment: {line.strip()}")

    sources = sorted(p for d in ("src", "cli") for p in (root / d).rglob("*")
                     if p.suffix in (".cpp", ".h"))
    for path in sources:
        scan(path, module_of_folder(path, root))
    for path in sorted((root / "include/dynpm").glob("*.h")):
        owner = owner_of_public_header(path.name, rules)
        if owner is None:
            problems.append(f"include/dynpm/{path.name}: no module's row in docs/architecture.md "
                            f"owns it")
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            m = INCLUDE.match(line)
            if m:
                check_include(path, number, m.group(1), m.group(2), owner)

    # The link graph: target_link_libraries(dynpm_<x> … dynpm_<y> …) needs y in x's "uses".
    for cmake in sorted(list((root / "src").glob("*/CMakeLists.txt")) + [root / "cli/CMakeLists.txt"]):
        folder = module_of_folder(cmake, root)
        _, allowed, _, public_only = rules[folder]
        text = re.sub(r"#.*", "", cmake.read_text())
        for call in re.finditer(r"target_link_libraries\s*\(([^)]*)\)", text):
            args = call.group(1).split()
            for lib in args[1:]:
                m = re.fullmatch(r"dynpm_(\w+)", lib)
                if not m or m.group(1) not in MODULES or "src/" + m.group(1) == folder:
                    continue
                if not public_only and m.group(1) not in allowed:
                    number = text[:call.start()].count("\n") + 1
                    problems.append(f"{cmake.relative_to(root)}:{number}: {args[0]} links "
                                    f"{lib}, which docs/architecture.md does not let {folder}/ use")

    if problems:
        print(f"{len(problems)} break(s) of the module rule (docs/architecture.md):")
        print("\n".join(problems))
        return 1
    print(f"module rule holds: {len(sources)} files of src/ and cli/, "
          f"{len(list((root / 'include/dynpm').glob('*.h')))} public headers")
    return 0


if __name__ == "__main__":
    sys.exit(main())
