"""Reading a clothfit measurement table (docs/formats.md) for the SciPy peers."""
import csv

import numpy as np


def read_columns(path):
    """The table's columns as numpy arrays keyed by lower-case name."""
    with open(path, newline="") as f:
        lines = [line for line in f if not line.startswith("#")]
    reader = csv.reader(lines)
    header = [h.strip().lower() for h in next(reader)]
    data = np.array([[float(x) for x in row] for row in reader if row])
    return {name: data[:, i] for i, name in enumerate(header)}
