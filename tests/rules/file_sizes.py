#!/usr/bin/env python3
"""No source file over 600 lines, except a reader of one format (src/io/, at most 900 lines)
that says at its top why it is long: a line "// Long: <reason>" among its first 20 lines.

Usage: file_sizes.py [REPO_ROOT]   (exit 0: the rule holds; 1: the files that break it)
"""
import pathlib
import sys

LIMIT, READER_LIMIT = 600, 900
FOLDERS = ["src", "include", "cli", "tests", "bench", "fuzz", "viewer/src", "viewer/test",
           "viewer/embed", "scripts"]
SUFFIXES = {".cpp", ".h", ".js", ".mjs", ".py", ".sh"}


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    problems, count = [], 0
    for folder in FOLDERS:
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in SUFFIXES or "node_modules" in path.parts or not path.is_file():
                continue
            count += 1
            lines = path.read_text(errors="replace").splitlines()
            rel = path.relative_to(root).as_posix()
            reason = any(l.startswith("// Long: ") for l in lines[:20])
            reader = rel.startswith("src/io/") and path.suffix == ".cpp"
            if len(lines) <= LIMIT:
                continue
            if reader and reason and len(lines) <= READER_LIMIT:
                continue
            if reader and not reason and len(lines) <= READER_LIMIT:
                problems.append(f"{rel}: {len(lines)} lines; a reader over {LIMIT} lines says why "
                                f"in a '// Long: …' line among its first 20")
            else:
                limit = READER_LIMIT if reader else LIMIT
                problems.append(f"{rel}: {len(lines)} lines, more than {limit}")
    if problems:
        print("\n".join(problems))
        return 1
    print(f"{count} files, none over {LIMIT} lines (readers with a reason: {READER_LIMIT})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
