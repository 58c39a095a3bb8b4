#!/usr/bin/env bash
# check-floors.sh [SOURCE_DIR]: fails when a file includes or links something from a higher floor.
#
# Floors, bottom to top (a file may use its own floor and the floors below it):
#   0  core/                        the algorithm (dammloam_core, dammloam_backend)
#   1  drivers/  io/  idl/          siblings on core: packet decoding, files, generated DDS types
#   2  services/                    DDS layer and the daemon
#   3  tools/                       command-line tools, benchmarks, simulator
#   4  tests/                       may use anything; scanned for nothing
#
# drivers <-> io: today neither includes the other (grep of every `#include "drivers/` under io/
# and `#include "io/` under drivers/ finds nothing) and neither library links the other
# (dammloam_drivers links only dammloam_core, dammloam_io/dammloam_pcd/dammloam_mapstore only
# core and io). The rule enforced is that the floor-1 siblings stay independent: drivers/, io/
# and idl/ may not include or link each other; whatever needs two of them lives on a higher
# floor (tools/driver joins drivers and io, services/dds joins idl and core).
#
# What is checked:
#   - every `#include "..."` in C/C++ sources and headers under core/ drivers/ io/ services/
#     tools/. A path starting with a floor folder ("io/tum.hpp") belongs to that floor; any other
#     path is resolved against the including file's folder ("../x.hpp", "helper.hpp") and judged
#     by where it lands. Paths that resolve to no file in the tree (headers generated into the
#     build tree such as "dammloam.h" from idl/) are not judged by the include scan; the library
#     that provides them is judged by the link scan.
#   - every library named in `target_link_libraries(...)` and after `LIBS` in any CMake call in a
#     CMakeLists.txt under those folders. Library names map to floors through the add_library()
#     calls of the whole tree (idl/ included); names that no add_library() defines (Eigen3::Eigen,
#     yaml-cpp, dammloam_options from cmake/) are external and not judged. The consumer's floor
#     is the folder of the CMakeLists.txt that holds the call.
# Out of scope: source files compiled in from other folders (target_sources with a path); they
# are not includes or links.
#
# Output: on stderr one line per violation, "file:line: include \"path\" (floor X) from floor Y"
# or "file:line: library name (floor X) from floor Y", and exit status 1; "floors: ok (...)" on
# stdout and status 0 when there is none.
set -euo pipefail
ROOT=${1:-"$(cd "$(dirname "$0")/.." && pwd)"}
exec python3 - "$ROOT" <<'PY'
import os, re, sys

root = os.path.abspath(sys.argv[1])
RANK = {"core": 0, "drivers": 1, "io": 1, "idl": 1, "services": 2, "tools": 3, "tests": 4}
SCANNED = ["core", "drivers", "io", "services", "tools"]
SOURCE_EXT = (".c", ".cc", ".cpp", ".cxx", ".h", ".hh", ".hpp", ".hxx", ".inl", ".ipp", ".tpp")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')


def floor_of(rel_path):
    top = rel_path.replace(os.sep, "/").split("/", 1)[0]
    return top if top in RANK else None


def allowed(user, used):
    """May a file on floor `user` use something on floor `used`?"""
    if user == used:
        return True
    if RANK[used] == RANK[user]:  # siblings on floor 1 stay independent
        return False
    return RANK[used] < RANK[user]


def walk(folder):
    for dirpath, dirnames, filenames in os.walk(os.path.join(root, folder)):
        dirnames[:] = sorted(d for d in dirnames if not d.startswith("."))
        for name in sorted(filenames):
            yield os.path.join(dirpath, name)


def cmake_calls(path):
    """(command, [(token, line)]) for every command call; comments and quotes handled."""
    text = open(path, encoding="utf-8", errors="replace").read()
    tokens, line, i, n = [], 1, 0, len(text)
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1; i += 1
        elif c.isspace():
            i += 1
        elif c == "#":
            m = re.match(r"#\[(=*)\[", text[i:])
            end = text.find("]" + m.group(1) + "]", i) if m else text.find("\n", i)
            end = n if end < 0 else end
            line += text.count("\n", i, end); i = end
        elif c in "()":
            tokens.append((c, line)); i += 1
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            tokens.append((text[i + 1:j], line)); line += text.count("\n", i, j); i = j + 1
        else:
            m = re.match(r'[^\s()"#]+', text[i:])
            tokens.append((m.group(0), line)); i += len(m.group(0))
    calls, k = [], 0
    while k < len(tokens):
        if k + 1 < len(tokens) and tokens[k + 1][0] == "(" and tokens[k][0] not in "()":
            name, depth, args, k = tokens[k][0].lower(), 1, [], k + 2
            while k < len(tokens) and depth:
                tok = tokens[k]
                depth += (tok[0] == "(") - (tok[0] == ")")
                if depth and tok[0] not in "()":
                    args.append(tok)
                k += 1
            calls.append((name, args))
        else:
            k += 1
    return calls


cmake_files = [p for f in RANK if os.path.isdir(os.path.join(root, f))
               for p in walk(f) if os.path.basename(p) == "CMakeLists.txt"]
library_floor = {}
for path in cmake_files:
    for name, args in cmake_calls(path):
        if name == "add_library" and args:
            library_floor[args[0][0]] = floor_of(os.path.relpath(path, root))

violations, n_includes, n_links = [], 0, 0
KEYWORDS = {"PUBLIC", "PRIVATE", "INTERFACE", "LINK_PUBLIC", "LINK_PRIVATE", "LINK_INTERFACE_LIBRARIES"}
for folder in SCANNED:
    if not os.path.isdir(os.path.join(root, folder)):
        continue
    for path in walk(folder):
        rel = os.path.relpath(path, root)
        if path.endswith(SOURCE_EXT):
            with open(path, encoding="utf-8", errors="replace") as fh:
                for number, text in enumerate(fh, 1):
                    m = INCLUDE.match(text)
                    if not m:
                        continue
                    inc = m.group(1)
                    used = floor_of(inc)
                    if used is None:
                        target = os.path.normpath(os.path.join(os.path.dirname(path), inc))
                        if not os.path.exists(target):
                            continue  # generated or external header
                        used = floor_of(os.path.relpath(target, root))
                        if used is None:
                            continue
                    n_includes += 1
                    if not allowed(folder, used):
                        violations.append(f"{rel}:{number}: include \"{inc}\" (floor {used}) "
                                          f"from floor {folder}")
        elif os.path.basename(path) == "CMakeLists.txt":
            for name, args in cmake_calls(path):
                if name == "target_link_libraries":
                    libs = args[1:]
                else:
                    libs, on = [], False
                    for tok in args:
                        if tok[0] == "LIBS":
                            on = True
                        elif on and re.fullmatch(r"[A-Z][A-Z0-9_]*", tok[0]):
                            on = False  # next keyword of the call (LABELS, SOURCES, ...)
                        elif on:
                            libs.append(tok)
                for lib, number in libs:
                    if lib in KEYWORDS:
                        continue
                    used = library_floor.get(lib)
                    if used is None:
                        continue  # external package or interface target outside the floors
                    n_links += 1
                    if not allowed(folder, used):
                        violations.append(f"{rel}:{number}: library {lib} (floor {used}) "
                                          f"from floor {folder}")

for v in violations:
    print(v, file=sys.stderr)
if violations:
    print(f"floors: {len(violations)} use(s) run up or sideways; "
          "rule: core <- drivers, io, idl <- services <- tools (tests: anything)", file=sys.stderr)
    sys.exit(1)
print(f"floors: ok ({n_includes} project includes, {n_links} project library links, "
      f"{len(library_floor)} libraries mapped)")
PY
