"""ref_view.py: a run's output file laid out as its blessed reference, by name, so that
numdiff compares each value with the reference's value of the same name
(tests/run_tests.sh): the reference's comment lines '# key value' by their key, its
column header and its columns by their names (a table), or its 'key value' lines by their
key (summary.txt). A column or key that the run has and the reference has not (a new
output) is left out, and named on stderr; one the reference has and the run has not makes
this exit 1, naming it. The rows are the run's, in its order.

Usage: ref_view.py REF NEW > VIEW
"""
import sys


def split(path):
    """(comment lines, the column names of its header or None, data lines) of a file: the
    header is the last comment line before the first data line, when the data are a table."""
    with open(path, encoding="utf-8", newline="") as f:
        lines = f.read().split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    comments, data = [], []
    for line in lines:
        (data if data or not line.startswith("#") else comments).append(line)
    return comments, data


def keyed(lines, strip):
    """{key: line} of lines 'KEY value' (after `strip`), and the keys in their order."""
    found, order = {}, []
    for line in lines:
        words = line[len(strip):].split() if line.startswith(strip) else []
        if words and words[0] not in found:
            found[words[0]] = line
            order.append(words[0])
    return found, order


def is_number(word):
    try:
        float(word)
        return True
    except ValueError:
        return False


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: ref_view.py REF NEW > VIEW")
    ref_path, new_path = sys.argv[1:]
    (ref_comments, ref_data), (new_comments, new_data) = split(ref_path), split(new_path)
    table = bool(ref_data) and is_number(ref_data[0].split()[0]) if ref_data and ref_data[0].split() else False
    missing, out = [], []
    header = ref_comments[-1] if table and ref_comments else None
    new_keys, _ = keyed(new_comments[:-1] if table and new_comments else new_comments, "#")
    for line in ref_comments:
        if line is header:
            continue
        words = line[1:].split()
        if not words:
            out.append(line)
        elif words[0] in new_keys:
            out.append(new_keys[words[0]])
        else:
            missing.append(f"comment '# {words[0]}'")
    extra = []
    if table:
        names = header[1:].split()
        new_names = new_comments[-1][1:].split() if new_comments else []
        place = {name: i for i, name in reversed(list(enumerate(new_names)))}
        missing += [f"column {name}" for name in names if name not in place]
        extra = [name for name in new_names if name not in set(names)]
        out.append(header)
        if not missing:
            for row in new_data:
                words = row.split()
                if len(words) != len(new_names):
                    sys.exit(f"ref_view.py: {new_path}: a row of {len(words)} values under a header of {len(new_names)} columns")
                out.append(" ".join(words[place[name]] for name in names))
    else:
        rows, order = keyed(new_data, "")
        ref_rows, ref_order = keyed(ref_data, "")
        missing += [f"key {key}" for key in ref_order if key not in rows]
        extra = [key for key in order if key not in ref_rows]
        out += [rows[key] for key in ref_order if key in rows]
    if missing:
        sys.exit(f"ref_view.py: {new_path} lacks what {ref_path} compares: {', '.join(missing)}")
    if extra:
        print(f"ref_view.py: {new_path}: not in {ref_path}, not compared: {' '.join(extra)}", file=sys.stderr)
    sys.stdout.write("".join(line + "\n" for line in out))


if __name__ == "__main__":
    main()
