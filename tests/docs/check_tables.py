#!/usr/bin/env python3
"""Checks the documentation against the measurements and the file tree.

Two checks over README.md and docs/**/*.md (python3, standard library only):

1. Tables. Every markdown table whose body holds a digit is preceded by an HTML comment that says
   where its numbers come from, and every number in it must equal that source, rounded to the
   digits the table shows. A table that holds no measurement (an option list, exit statuses, a
   picture grid) says so with `<!-- table: static -->` (any text may follow `static`).

   The comment, one directive per line:

       <!-- table
       csv: tests/bench/results/render/table1.csv      the source; its alias is `csv`
       csv: gpu=tests/bench/results/render/table1_gpu.csv   more sources, each with an alias
       where: samples=1, cull=back                       filters every lookup
       key: Model                                        columns whose cells pick the CSV row
       complete: yes                                     every CSV row passing `where` is shown
       Model => {model}                                  a column: its cells' template
       Note => text                                      a column of words, not checked
       row 3 FPS => {fps@model=bunny}                    one cell (body row 3, from 1) instead
       -->

   A template is the cell's text with placeholders `{[alias:]field[@f=v,f=v][|mod|mod]}`:
   `field` a column of the CSV (alias `csv` when none is given), `@f=v,...` filters that replace
   or add to the row's own (`where` and the key columns' values), `mod` one of `pct` (x 100),
   `*N` or `/N` (scale), `abs`, `min` or `max` (over all the rows that match: a range's ends).
   A filter value with `*` is a wildcard (`scene=bunny-*`). Without `min`/`max` the lookup must
   find exactly one CSV row. A key column's cells
   are matched against its template and the text each placeholder covers becomes a filter
   (field = that text) for the row. A filter on a field that a CSV does not have is ignored for
   that CSV.

   A cell's text (with `**` and backticks removed, spaces collapsed) must match its template,
   and each placeholder's text must equal the CSV value: numbers as shown, i.e. within half a
   unit of the last digit shown (`0.71` matches 0.714 and 0.705; `1.8e7` matches 1.84e7; commas
   and a leading `+` are ignored), anything else as the same string (an empty CSV value shows as
   `-`). A column that the comment does not name must hold no digit. CSV lines that start with
   `#` are comments.

2. Links. Every relative link or image in those files names a file or folder that exists inside
   the repository, and a `#fragment` names a heading of the markdown file it points to (GitHub's
   anchors).

Exits 0 when all hold, 1 naming each document, table, row and cell that disagrees. `--self-test`
runs the checks on small fixtures and exits non-zero unless they catch what they must. `--fix`
rewrites each number that disagrees with its CSV to the CSV's value, shown to the digits it had
(numbers in scientific notation and cells that do not have their column's form are left to be
fixed by hand), then reports what still disagrees.
"""

import argparse
import csv
import fnmatch
import io
import math
import re
import sys
import tempfile
from decimal import Decimal, InvalidOperation
from pathlib import Path

DOC_GLOBS = ["README.md", "docs/**/*.md"]


class DocError(Exception):
    pass


# ---------------------------------------------------------------------------------------------
# Markdown scanning


def strip_fences(lines):
    """Yields (index, line, in_code) with fenced code blocks marked."""
    fence = None
    for i, line in enumerate(lines):
        stripped = line.lstrip()
        if fence is None and (stripped.startswith("```") or stripped.startswith("~~~")):
            fence = stripped[:3]
            yield i, line, True
            continue
        if fence is not None:
            if stripped.startswith(fence):
                fence = None
            yield i, line, True
            continue
        yield i, line, False


def split_row(line):
    """The cells of a table line `| a | b |`, honouring `\\|` and code spans."""
    text = line.strip()
    if text.startswith("|"):
        text = text[1:]
    if text.endswith("|") and not text.endswith("\\|"):
        text = text[:-1]
    cells, current, in_code = [], [], False
    i = 0
    while i < len(text):
        c = text[i]
        if c == "\\" and i + 1 < len(text) and text[i + 1] == "|":
            current.append("|")
            i += 2
            continue
        if c == "`":
            in_code = not in_code
        if c == "|" and not in_code:
            cells.append("".join(current).strip())
            current = []
        else:
            current.append(c)
        i += 1
    cells.append("".join(current).strip())
    return cells


DELIMITER = re.compile(r"^\s*\|?\s*:?-{3,}:?\s*(\|\s*:?-{3,}:?\s*)*\|?\s*$")


def find_tables(lines):
    """Markdown tables: dicts with the header line index, headers, body rows (line, cells)."""
    tables = []
    marked = list(strip_fences(lines))
    i = 0
    while i < len(marked) - 1:
        idx, line, in_code = marked[i]
        nxt_idx, nxt, nxt_code = marked[i + 1]
        if (not in_code and not nxt_code and line.lstrip().startswith("|")
                and DELIMITER.match(nxt)):
            headers = split_row(line)
            body = []
            j = i + 2
            while j < len(marked) and not marked[j][2] and marked[j][1].lstrip().startswith("|"):
                body.append((marked[j][0], split_row(marked[j][1])))
                j += 1
            tables.append({"line": idx, "headers": headers, "body": body})
            i = j
        else:
            i += 1
    return tables


def comment_before(lines, line_index):
    """The text of an HTML comment that ends right before line_index (blank lines allowed)."""
    j = line_index - 1
    while j >= 0 and not lines[j].strip():
        j -= 1
    if j < 0 or not lines[j].rstrip().endswith("-->"):
        return None
    end = j
    while j >= 0 and "<!--" not in lines[j]:
        j -= 1
    if j < 0:
        return None
    text = "\n".join(lines[j:end + 1])
    start = text.index("<!--")
    return text[start + 4:text.rindex("-->")].strip()


# ---------------------------------------------------------------------------------------------
# CSV sources and the table comment


class Source:
    def __init__(self, root, rel):
        self.rel = rel
        path = (root / rel).resolve()
        if not path.is_file():
            raise DocError(f"source {rel} does not exist")
        text = path.read_text(encoding="utf-8")
        lines = [l for l in text.splitlines() if not l.lstrip().startswith("#") and l.strip()]
        reader = csv.DictReader(io.StringIO("\n".join(lines)))
        self.fields = reader.fieldnames or []
        self.rows = [{k.strip(): (v or "").strip() for k, v in r.items() if k is not None}
                     for r in reader]

    def matching(self, filters):
        active = {k: v for k, v in filters.items() if k in self.fields}
        rows = [r for r in self.rows if all(same_value(r.get(k, ""), v) for k, v in active.items())]
        return rows, ", ".join(f"{k}={v}" for k, v in active.items()) or "no filter"

    def lookup(self, filters, what, many=False):
        rows, desc = self.matching(filters)
        if len(rows) != 1 and not (many and rows):
            need = "at least 1" if many else "exactly 1"
            raise DocError(f"{what}: {len(rows)} rows of {self.rel} match {desc} (need {need})")
        return rows if many else rows[0]


def parse_number(text):
    t = text.strip().replace(",", "").replace("\u2212", "-").replace("\u2009", "")
    if t.startswith("+"):
        t = t[1:]
    try:
        d = Decimal(t)
    except InvalidOperation:
        return None
    if not d.is_finite():
        return None
    return d


def same_value(csv_value, wanted):
    if csv_value == wanted:
        return True
    if "*" in wanted:
        return fnmatch.fnmatchcase(csv_value, wanted)
    a, b = parse_number(csv_value), parse_number(wanted)
    return a is not None and b is not None and a == b


PLACEHOLDER = re.compile(r"\{([^{}]+)\}")


class Placeholder:
    def __init__(self, spec):
        self.spec = spec
        parts = spec.split("|")
        head, self.mods = parts[0].strip(), [m.strip() for m in parts[1:]]
        self.filters = {}
        if "@" in head:
            head, filt = head.split("@", 1)
            for item in filt.split(","):
                if "=" not in item:
                    raise DocError(f"placeholder {{{spec}}}: filter '{item}' is not field=value")
                k, v = item.split("=", 1)
                self.filters[k.strip()] = v.strip()
        head = head.strip()
        self.alias, self.field = (head.split(":", 1) if ":" in head else ("csv", head))
        self.alias, self.field = self.alias.strip(), self.field.strip()
        for m in self.mods:
            if m not in ("pct", "abs", "min", "max") and not re.fullmatch(r"[*/][0-9.eE+-]+", m):
                raise DocError(f"placeholder {{{spec}}}: unknown modifier '{m}'")
        self.aggregate = next((m for m in self.mods if m in ("min", "max")), None)

    def transform(self, value):
        for m in self.mods:
            if m in ("min", "max"):
                continue
            if m == "pct":
                value *= 100
            elif m == "abs":
                value = abs(value)
            elif m[0] == "*":
                value *= float(m[1:])
            else:
                value /= float(m[1:])
        return value


class Template:
    def __init__(self, text):
        self.text = text
        self.placeholders = []
        pattern = []
        pos = 0
        for m in PLACEHOLDER.finditer(text):
            pattern.append(literal_pattern(text[pos:m.start()]))
            pattern.append("(.+?)")
            self.placeholders.append(Placeholder(m.group(1)))
            pos = m.end()
        pattern.append(literal_pattern(text[pos:]))
        self.regex = re.compile("^" + "".join(pattern) + "$", re.S)

    def match(self, cell):
        return self.regex.match(cell)


def literal_pattern(text):
    out = []
    for piece in re.split(r"(\s+)", text):
        if not piece:
            continue
        out.append(r"\s*" if piece.isspace() else re.escape(piece))
    return "".join(out)


def normalize_cell(cell):
    text = cell.replace("**", "").replace("`", "").replace("__", "")
    return re.sub(r"\s+", " ", text).strip()


class Spec:
    def __init__(self, root, text):
        self.sources = {}
        self.where = {}
        self.keys = []
        self.complete = False
        self.columns = {}
        self.cells = {}
        body = text[len("table"):].strip()
        if body.startswith(":"):
            body = body[1:].strip()
        for raw in body.splitlines():
            line = raw.strip()
            if not line:
                continue
            m = re.match(r"^row\s+(\d+)\s+(.*?)\s*=>\s*(.*)$", line)
            if m:
                self.cells[(int(m.group(1)), m.group(2))] = column_spec(m.group(3))
                continue
            if "=>" in line:
                header, tmpl = line.split("=>", 1)
                self.columns[header.strip()] = column_spec(tmpl.strip())
                continue
            if ":" not in line:
                raise DocError(f"table comment line '{line}' is neither 'name: value' nor "
                               "'Header => template'")
            name, value = (s.strip() for s in line.split(":", 1))
            if name == "csv":
                alias, path = value.split("=", 1) if "=" in value else ("csv", value)
                alias = alias.strip()
                if not self.sources:
                    self.sources["csv"] = Source(root, path.strip())
                    if alias != "csv":
                        self.sources[alias] = self.sources["csv"]
                else:
                    self.sources[alias] = Source(root, path.strip())
            elif name == "where":
                for item in value.split(","):
                    if item.strip():
                        k, v = item.split("=", 1)
                        self.where[k.strip()] = v.strip()
            elif name == "key":
                self.keys = [k.strip() for k in value.split(",") if k.strip()]
            elif name == "complete":
                self.complete = value.lower() in ("yes", "true", "1")
            else:
                raise DocError(f"table comment: unknown directive '{name}'")
        if not self.sources:
            raise DocError("table comment names no csv")


def column_spec(text):
    return None if text == "text" else Template(text)


# ---------------------------------------------------------------------------------------------
# Checking one table


def compare(placeholder, shown, row, source):
    """None when the shown text equals the CSV value of the placeholder, else the reason."""
    if placeholder.aggregate:
        values = [parse_number(r.get(placeholder.field, "")) for r in row]
        if placeholder.field not in source.fields or any(v is None for v in values):
            return f"{source.rel}: '{placeholder.field}' is not a number in every matching row"
        value = str((min if placeholder.aggregate == "min" else max)(values))
    else:
        value = row.get(placeholder.field)
    if value is None:
        return f"{source.rel} has no column '{placeholder.field}'"
    number = parse_number(value)
    shown_number = parse_number(shown)
    if number is not None and not placeholder.mods and shown_number is None:
        return f"shows '{shown}', {source.rel} has {placeholder.field}={value}"
    if number is not None and shown_number is not None:
        exact = placeholder.transform(float(number))
        quantum = 10.0 ** shown_number.as_tuple().exponent
        if math.isclose(float(shown_number), exact, rel_tol=1e-12, abs_tol=0.5 * quantum * 1.000001):
            return None
        return (f"shows {shown}, {source.rel} has {placeholder.field}={value}"
                + (f" ({exact:.6g} after {'|'.join(placeholder.mods)})" if placeholder.mods else ""))
    if value == "" and shown.strip() in ("", "-", "\u2013", "\u2014"):
        return None
    if shown.strip() == value:
        return None
    return f"shows '{shown}', {source.rel} has {placeholder.field}='{value}'"


def corrected(placeholder, shown, row, source):
    """The CSV's value shown as `shown` is (its decimals, thousands separators and sign), or None
    when either is not a plain number."""
    if placeholder.aggregate:
        values = [parse_number(r.get(placeholder.field, "")) for r in row]
        if any(v is None for v in values) or not values:
            return None
        number = (min if placeholder.aggregate == "min" else max)(values)
    else:
        number = parse_number(row.get(placeholder.field) or "")
    shown_number = parse_number(shown)
    if number is None or shown_number is None or re.search(r"[eE]", shown):
        return None
    value = placeholder.transform(float(number))
    decimals = max(0, -shown_number.as_tuple().exponent)
    text = f"{value:,.{decimals}f}" if "," in shown else f"{value:.{decimals}f}"
    return "+" + text if shown.strip().startswith("+") and value >= 0 else text


def check_table(root, doc, lines, table, errors, fixes=None):
    headers = table["headers"]
    has_digit = any(re.search(r"\d", c) for _, cells in table["body"] for c in cells)
    comment = comment_before(lines, table["line"])
    where = f"{doc}:{table['line'] + 1}: table '{' | '.join(h[:24] for h in headers)}'"
    if comment is None or not re.match(r"^table\b", comment):
        if has_digit:
            errors.append(f"{where}: holds numbers but no <!-- table ... --> comment before it "
                          "(or <!-- table: static --> when it is not a measurement)")
        return
    if re.match(r"^table\s*:\s*static\b", comment):
        return
    try:
        spec = Spec(root, comment)
    except DocError as e:
        errors.append(f"{where}: {e}")
        return
    for name in list(spec.columns) + [h for _, h in spec.cells] + spec.keys:
        if name not in headers:
            errors.append(f"{where}: the comment names column '{name}', the table has "
                          f"{headers}")
            return
    for name in spec.keys:
        if spec.columns.get(name) is None:
            errors.append(f"{where}: key column '{name}' needs a template")
            return
    shown_rows = {alias: [] for alias in spec.sources}
    for n, (line_idx, cells) in enumerate(table["body"], start=1):
        loc = f"{doc}:{line_idx + 1}: row {n}"
        cells = cells + [""] * (len(headers) - len(cells))
        filters = dict(spec.where)
        ok = True
        for name in spec.keys:
            cell = normalize_cell(cells[headers.index(name)])
            tmpl = spec.columns[name]
            m = tmpl.match(cell)
            if not m:
                errors.append(f"{loc}, key column '{name}': '{cell}' does not have the form "
                              f"'{tmpl.text}'")
                ok = False
                break
            for ph, text in zip(tmpl.placeholders, m.groups()):
                filters[ph.field] = text.strip()
        if not ok:
            continue
        label = ", ".join(f"{k}={v}" for k, v in filters.items() if k not in spec.where)
        if label:
            loc += f" ({label})"
        for alias, source in spec.sources.items():
            try:
                shown_rows[alias].append(id(source.lookup(filters, "")))
            except DocError:
                pass
        for col, header in enumerate(headers):
            cell = normalize_cell(cells[col])
            tmpl = spec.cells.get((n, header), spec.columns.get(header, "undeclared"))
            if (n, header) not in spec.cells and header not in spec.columns:
                if re.search(r"\d", cell):
                    errors.append(f"{loc}, column '{header}': '{cell}' holds a number but the "
                                  "comment declares no template for the column ('=> text' for "
                                  "words)")
                continue
            if tmpl is None or header in spec.keys and (n, header) not in spec.cells:
                continue
            m = tmpl.match(cell)
            if not m:
                errors.append(f"{loc}, column '{header}': '{cell}' does not have the form "
                              f"'{tmpl.text}'")
                continue
            for ph, text in zip(tmpl.placeholders, m.groups()):
                source = spec.sources.get(ph.alias)
                if source is None:
                    errors.append(f"{loc}, column '{header}': no csv with alias '{ph.alias}'")
                    continue
                try:
                    row = source.lookup({**filters, **ph.filters}, "", many=bool(ph.aggregate))
                except DocError as e:
                    errors.append(f"{loc}, column '{header}', {{{ph.spec}}}{e}")
                    continue
                problem = compare(ph, text.strip(), row, source)
                if problem and fixes is not None:
                    new = corrected(ph, text.strip(), row, source)
                    if new is not None:
                        fixes.append((line_idx, col, text.strip(), new))
                        continue
                if problem:
                    errors.append(f"{loc}, column '{header}': {problem}")
    if spec.complete:
        source = spec.sources["csv"]
        active = {k: v for k, v in spec.where.items() if k in source.fields}
        wanted = [r for r in source.rows
                  if all(same_value(r.get(k, ""), v) for k, v in active.items())]
        shown = set(shown_rows["csv"])
        missing = [r for r in wanted if id(r) not in shown]
        if missing:
            first = ", ".join(f"{k}={v}" for k, v in list(missing[0].items())[:3])
            errors.append(f"{where}: 'complete' but {len(missing)} rows of {source.rel} are not "
                          f"shown (first: {first})")


# ---------------------------------------------------------------------------------------------
# Links


LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
CODE_SPAN = re.compile(r"`+[^`]*`+")


def github_anchor(heading):
    text = re.sub(r"[`*_]", "", heading.strip().lower())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors_of(path):
    anchors, counts = set(), {}
    for _, line, in_code in strip_fences(path.read_text(encoding="utf-8").splitlines()):
        if in_code:
            continue
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            base = github_anchor(m.group(1))
            n = counts.get(base, 0)
            anchors.add(base if n == 0 else f"{base}-{n}")
            counts[base] = n + 1
    return anchors


def check_links(root, doc_path, errors):
    doc = doc_path.relative_to(root)
    for idx, line, in_code in strip_fences(doc_path.read_text(encoding="utf-8").splitlines()):
        if in_code:
            continue
        text = CODE_SPAN.sub("", line)
        for m in LINK.finditer(text):
            target = m.group(1)
            if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target):
                continue
            path_part, _, fragment = target.partition("#")
            dest = doc_path if not path_part else (doc_path.parent / path_part)
            try:
                resolved = dest.resolve()
            except OSError:
                resolved = dest
            loc = f"{doc}:{idx + 1}: link '{target}'"
            if root.resolve() not in resolved.parents and resolved != root.resolve():
                errors.append(f"{loc} leaves the repository")
                continue
            if not resolved.exists():
                errors.append(f"{loc}: {resolved.relative_to(root.resolve())} does not exist")
                continue
            if fragment and resolved.suffix == ".md" and resolved.is_file():
                if fragment not in anchors_of(resolved):
                    errors.append(f"{loc}: no heading '#{fragment}' in "
                                  f"{resolved.relative_to(root.resolve())}")


# ---------------------------------------------------------------------------------------------


def documents(root):
    found = []
    for pattern in DOC_GLOBS:
        found.extend(sorted(p for p in root.glob(pattern) if p.is_file()))
    return found


def cell_spans(line):
    """(start, end) of each cell of a table line in the line's text, as split_row splits it."""
    spans, start, in_code = [], None, False
    i = 0
    while i < len(line):
        c = line[i]
        if c == "\\" and i + 1 < len(line) and line[i + 1] == "|":
            i += 2
            continue
        if c == "`":
            in_code = not in_code
        if c == "|" and not in_code:
            if start is not None:
                spans.append((start, i))
            start = i + 1
        i += 1
    if start is not None and line[start:].strip():
        spans.append((start, len(line)))
    return spans


def apply_fixes(lines, fixes):
    """Rewrites the numbers of `fixes` (line, column, shown, new) in `lines`, each cell's left to
    right."""
    for line_idx in sorted({f[0] for f in fixes}):
        line = lines[line_idx]
        spans = cell_spans(line)
        edits = []  # (start, end, new) in the line
        cursor = {}
        for _, col, old, new in (f for f in fixes if f[0] == line_idx):
            start, end = spans[col]
            at = line.find(old, cursor.get(col, start), end)
            if at < 0:
                continue
            edits.append((at, at + len(old), new))
            cursor[col] = at + len(old)
        for start, end, new in sorted(edits, reverse=True):
            line = line[:start] + new + line[end:]
        lines[line_idx] = line


def run(root, tables=True, links=True, fix=False):
    errors = []
    for path in documents(root):
        doc = path.relative_to(root)
        if tables:
            text = path.read_text(encoding="utf-8")
            lines = text.splitlines()
            fixes = [] if fix else None
            for table in find_tables(lines):
                check_table(root, doc, lines, table, errors, fixes)
            if fixes:
                apply_fixes(lines, fixes)
                path.write_text("\n".join(lines) + ("\n" if text.endswith("\n") else ""),
                                encoding="utf-8")
                print(f"{doc}: {len(fixes)} numbers rewritten from their CSVs")
        if links:
            check_links(root, path, errors)
    return errors


# ---------------------------------------------------------------------------------------------
# Self-test: the checks pass on a correct fixture and catch each kind of mistake.

FIXTURE_CSV = """# a comment line
model,triangles,median_ms,fps,share,samples
bunny,3674,14.87,67.2,0.0123,1
bunny,3674,0.817,1224,0.5,4
dragon,871306,115.73,8.6,0.25,1
"""

GOOD_TABLE = """<!-- table
csv: tests/bench/results/x/table.csv
where: samples=1
key: Model
complete: yes
Model => {model}
Triangles => {triangles}
ms/frame (FPS) => {median_ms} ({fps})
Share => {share|pct} %
MSAA FPS => {fps@samples=4}
Note => text
row 2 MSAA FPS => -
-->

| Model | Triangles | ms/frame (FPS) | Share | MSAA FPS | Note |
| --- | ---: | ---: | ---: | ---: | --- |
| bunny | 3,674 | **14.9** (67) | 1.2 % | 1224 | 2 cores |
| dragon | 871306 | 115.73 (8.6) | 25 % | - | words |
"""

RANGE_TABLE = """<!-- table
csv: tests/bench/results/x/table.csv
Range => {median_ms@model=*|min}-{median_ms@model=*|max} ms, bunny {share@model=bun*|max|pct} %
-->
| Range |
| --- |
| 0.817-115.73 ms, bunny 50 % |
"""


def self_test():
    cases = [
        ("a correct table, links and a static table", GOOD_TABLE
         + "\n<!-- table: static (exit statuses) -->\n| status | meaning |\n| --- | --- |\n| 2 | usage |\n"
         + "\nSee [the other page](docs/other.md#a-heading) and [here](#title).\n", []),
        ("a wrong cell", GOOD_TABLE.replace("(67)", "(68)"), ["row 1", "fps=67.2"]),
        ("a cell rounded wrongly", GOOD_TABLE.replace("**14.9**", "14.8"), ["median_ms=14.87"]),
        ("a percentage off", GOOD_TABLE.replace("1.2 %", "1.3 %"), ["share=0.0123"]),
        ("a table without a comment", "| a | b |\n| --- | --- |\n| x | 1.5 |\n",
         ["no <!-- table"]),
        ("a number in an undeclared column", GOOD_TABLE.replace("Note => text\n", ""),
         ["declares no template"]),
        ("a row left out of a complete table",
         GOOD_TABLE.replace("| dragon | 871306 | 115.73 (8.6) | 25 % | - | words |\n", ""),
         ["not shown"]),
        ("a range from min and max", RANGE_TABLE, []),
        ("a range's end off", RANGE_TABLE.replace("115.73", "115.8"), ["115.8"]),
        ("a key the CSV lacks", GOOD_TABLE.replace("| dragon |", "| teapot |"), ["0 rows"]),
        ("a broken link", "See [nothing](missing.md).\n", ["does not exist"]),
        ("a link to a missing heading", "See [x](docs/other.md#no-such-heading).\n",
         ["no heading"]),
        ("a link out of the repository", "See [x](../../outside.md).\n", ["leaves"]),
    ]
    failures = 0
    for name, text, expected in cases:
        with tempfile.TemporaryDirectory() as tmp:
            root = Path(tmp)
            (root / "tests/bench/results/x").mkdir(parents=True)
            (root / "tests/bench/results/x/table.csv").write_text(FIXTURE_CSV)
            (root / "docs").mkdir()
            (root / "docs/other.md").write_text("# Other\n\n## A heading\n")
            (root / "README.md").write_text("# Title\n\n" + text)
            errors = run(root)
        if not expected:
            ok = not errors
        else:
            ok = bool(errors) and all(any(e_part in e for e in errors) for e_part in expected)
        print(f"{'ok  ' if ok else 'FAIL'} {name}" + ("" if ok else f": got {errors}"))
        failures += not ok
    # --fix: wrong numbers rewritten to their CSV values at the digits shown, the rest kept.
    broken = (GOOD_TABLE.replace("(67)", "(68)").replace("**14.9**", "**14.8**")
              .replace("1.2 %", "1.3 %").replace("115.73 (8.6)", "115.70 (8.6)"))
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "tests/bench/results/x").mkdir(parents=True)
        (root / "tests/bench/results/x/table.csv").write_text(FIXTURE_CSV)
        (root / "README.md").write_text("# Title\n\n" + broken)
        run(root, links=False, fix=True)
        fixed = (root / "README.md").read_text()
        errors = run(root, links=False)
    ok = not errors and fixed == "# Title\n\n" + GOOD_TABLE
    print(f"{'ok  ' if ok else 'FAIL'} --fix rewrites wrong numbers" + ("" if ok else f": {errors}"))
    failures += not ok
    total = len(cases) + 1
    print(f"self-test: {total - failures} of {total} cases behave")
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", default=str(Path(__file__).resolve().parents[2]),
                        help="the repository root (default: two folders above this script)")
    parser.add_argument("--self-test", action="store_true",
                        help="check that the checks catch mistakes in small fixtures")
    parser.add_argument("--tables-only", action="store_true", help="skip the link check")
    parser.add_argument("--links-only", action="store_true", help="skip the table check")
    parser.add_argument("--fix", action="store_true",
                        help="rewrite the numbers that disagree with their CSVs, then check")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    root = Path(args.root).resolve()
    if args.fix and not args.links_only:
        run(root, tables=True, links=False, fix=True)
    errors = run(root, tables=not args.links_only, links=not args.tables_only)
    for e in errors:
        print(e)
    docs = len(documents(root))
    if errors:
        print(f"check_tables: {len(errors)} problems in {docs} documents")
        return 1
    print(f"check_tables: {docs} documents, tables and links agree")
    return 0


if __name__ == "__main__":
    sys.exit(main())
