#!/usr/bin/env python3
"""The libraries' dependency graph, read from the code, and the layering rules it must keep.

Reads every #include "lib/..." of lib/<library>/ and tools/ and checks:
  1. no two files include each other, directly or through others (a cycle among a library's
     files, or across libraries: a "two-way include");
  2. the libraries' graph has no cycle;
  3. every library a library includes is one its CMakeLists.txt links (target_link_libraries
     names sss_<library>, directly or through the libraries it links);
  4. docs/design.md holds the graph as this script draws it, between the lines
     <!-- dependency-graph:begin --> and <!-- dependency-graph:end -->.

  dependency_graph.py --root DIR            check, exit 1 naming what fails
  dependency_graph.py --root DIR --write    rewrite docs/design.md's graph, then check
"""
import argparse
import re
import sys
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/([a-z_0-9]+)\.h"', re.MULTILINE)
LINKS = re.compile(r"target_link_libraries\(\s*sss_(\w+)(.*?)\)", re.DOTALL)
BEGIN, END = "<!-- dependency-graph:begin -->", "<!-- dependency-graph:end -->"


def modules(root):
    """{(library, module): set of (library, module) it includes}, a module being a .h/.cpp pair."""
    graph = {}
    for path in sorted((root / "lib").glob("*/*")):
        if path.suffix not in (".h", ".cpp"):
            continue
        node = (path.parent.name, path.stem)
        edges = graph.setdefault(node, set())
        for library, name in INCLUDE.findall(path.read_text()):
            if (library, name) != node and (root / "lib" / library / f"{name}.h").exists():
                edges.add((library, name))
    return graph


def cycles(graph):
    """The strongly connected components with more than one node (Tarjan), each sorted."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(node):
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for successor in sorted(graph.get(node, ())):
            if successor not in index:
                visit(successor)
                low[node] = min(low[node], low[successor])
            elif successor in on_stack:
                low[node] = min(low[node], index[successor])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    sys.setrecursionlimit(10000)
    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def library_graph(module_graph):
    graph = {}
    for (library, _), edges in module_graph.items():
        graph.setdefault(library, set()).update(l for l, _ in edges if l != library)
    return graph


def linked_libraries(root):
    """{library: the sss_ libraries its CMakeLists.txt links}."""
    linked = {}
    for cmake in sorted((root / "lib").glob("*/CMakeLists.txt")):
        for name, rest in LINKS.findall(cmake.read_text()):
            linked.setdefault(name, set()).update(re.findall(r"\bsss_(\w+)", rest))
    return linked


def reachable(graph, start):
    seen, todo = set(), [start]
    while todo:
        for successor in graph.get(todo.pop(), ()):
            if successor not in seen:
                seen.add(successor)
                todo.append(successor)
    return seen


def layers(graph):
    """Each library's depth: 0 for one that includes no other library."""
    depth = {}

    def of(library):
        if library not in depth:
            depth[library] = 1 + max((of(d) for d in graph.get(library, ())), default=-1)
        return depth[library]

    for library in graph:
        of(library)
    return depth


def mermaid(graph):
    """The graph as a Mermaid flowchart, dependencies below their users, without the edges that
    a longer path already implies (the transitive reduction), so that it stays readable."""
    lines = ["```mermaid", "flowchart TD"]
    for library in sorted(graph, key=lambda l: (-layers(graph)[l], l)):
        for dependency in sorted(graph[library]):
            implied = any(dependency in reachable(graph, other)
                          for other in graph[library] if other != dependency)
            if not implied:
                lines.append(f"  {library} --> {dependency}")
    lines.append("```")
    return "\n".join(lines)


def check(root, write):
    problems = []
    module_graph = modules(root)
    for component in cycles(module_graph):
        names = ", ".join(f"lib/{l}/{m}" for l, m in component)
        problems.append(f"files that include each other (a cycle): {names}")
    graph = library_graph(module_graph)
    for component in cycles(graph):
        problems.append(f"libraries that depend on each other: {', '.join(component)}")
    linked = linked_libraries(root)
    for library, dependencies in sorted(graph.items()):
        allowed = reachable(linked, library)
        for dependency in sorted(dependencies - allowed):
            problems.append(f"lib/{library} includes lib/{dependency} but its CMakeLists.txt "
                            f"does not link sss_{dependency}")
    design = root / "docs" / "design.md"
    drawn = f"{BEGIN}\n{mermaid(graph)}\n{END}"
    if not design.exists():
        problems.append(f"{design}: missing (it holds the dependency graph)")
    else:
        text = design.read_text()
        if BEGIN not in text or END not in text:
            problems.append(f"{design}: no {BEGIN} ... {END} section")
        else:
            start, stop = text.index(BEGIN), text.index(END) + len(END)
            if write:
                text = text[:start] + drawn + text[stop:]
                design.write_text(text)
            elif text[start:stop] != drawn:
                problems.append(f"{design}: the dependency graph differs from the code's; run "
                                f"tests/design/dependency_graph.py --root . --write")
    for problem in problems:
        print(f"dependency_graph: {problem}", file=sys.stderr)
    return 1 if problems else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=Path, default=Path(__file__).resolve().parents[2])
    parser.add_argument("--write", action="store_true", help="rewrite docs/design.md's graph")
    args = parser.parse_args()
    return check(args.root.resolve(), args.write)


if __name__ == "__main__":
    sys.exit(main())
