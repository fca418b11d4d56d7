"""Report helpers shared by the experiment scripts (sweep, paper_tables, lifelong): summary numbers
of a sample, their formatting, progress lines, and rewriting the generated blocks of a markdown file
(`<!-- paper_tables:X begin -->` ... `end`, `<!-- lifelong:begin ... -->` ... `end`) while leaving
the hand-written text around them as it is.
"""
import os
import statistics
import sys


def log(*parts):
    """A progress line on stderr."""
    print(*parts, file=sys.stderr, flush=True)


def mean_std(values):
    """(mean, sample standard deviation) of the values that are not None; std 0 for one value;
    None when there is no value."""
    values = [v for v in values if v is not None]
    if not values:
        return None
    return statistics.fmean(values), (statistics.stdev(values) if len(values) > 1 else 0.0)


def fmt_mean_std(ms, digits=3):
    """'m ± s' of a mean_std result, 'm' alone when s is 0 (one value), '–' for None."""
    if ms is None:
        return "–"
    m, s = ms
    return f"{m:.{digits}f} ± {s:.{digits}f}" if s else f"{m:.{digits}f}"


def write_atomic(path, text):
    """Writes through a temporary file and a rename, so a reader never sees a torn file."""
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def replace_generated_block(path, begin, end, body, title, text_if_missing=""):
    """Puts `begin\\nbody\\nend` in place of the text from the `begin` marker to the `end` marker
    after it; without the markers, appends a `## title` section holding the block. Everything
    else in the file stays as it is. A missing file starts as text_if_missing."""
    text = open(path).read() if os.path.isfile(path) else text_if_missing
    block = f"{begin}\n{body}\n{end}"
    a = text.find(begin)
    b = text.find(end, a + len(begin)) if a >= 0 else -1
    if a >= 0 and b >= 0:
        text = text[:a] + block + text[b + len(end):]
    else:
        text = text.rstrip("\n") + f"\n\n## {title}\n\n{block}\n"
    write_atomic(path, text)
