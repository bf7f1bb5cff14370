# SPDX-License-Identifier: GPL-2.0-or-later
# The Python side of tests/cli/python_module_test.cpp: imports the module that
# `mbsc generate --python` wrote, calls every function at the state the C++ reference
# driver (reference_driver.cpp) used, and compares with what the driver printed; then
# the defaults, the shape checks and the exceptions. Prints "checked N values" and
# exits 0, or prints what differs and exits 1.
#   usage: check_python_module.py MODULE_DIR NAME REFERENCE_FILE [LIBRARY]
import importlib
import math
import sys

import numpy as np

module_dir, name, reference = sys.argv[1], sys.argv[2], sys.argv[3]
sys.path.insert(0, module_dir)
mod = importlib.import_module(name)
model = mod.Model(sys.argv[4]) if len(sys.argv) > 4 else mod.Model()

failures = []
checked = 0


def fail(text):
    failures.append(text)


tables, indices, inputs, calls = {}, {}, {}, {}
for line in open(reference):
    words = line.split()
    if words[0] == "names":
        tables[words[1]] = tuple(words[3:3 + int(words[2])])
    elif words[0] == "index":
        indices[words[1]] = tuple(int(v) for v in words[3:3 + int(words[2])])
    elif words[0] == "input":
        inputs[words[1]] = np.array([float(v) for v in words[3:]], dtype=np.float64)
    elif words[0] == "call":
        calls[words[1]] = (int(words[2]), np.array([float(v) for v in words[4:]], dtype=np.float64))

# The name tables and sizes written into the module are the header's.
for table, names in tables.items():
    if tuple(getattr(mod, table)) != names:
        fail("%s: module has %s, C++ has %s" % (table, getattr(mod, table), names))
for table, values in indices.items():
    if tuple(getattr(mod, table)) != values:
        fail("%s: module has %s, C++ has %s" % (table, getattr(mod, table), values))
for size, table in (("kNx", "kStateNames"), ("kNxFull", "kFullStateNames"), ("kNdof", "kDofNames"),
                    ("kNin", "kInputNames"), ("kNp", "kParamNames"), ("kNc", "kConstraintNames"), ("kNy", "kOutputNames")):
    if getattr(mod, size) != len(tables[table]):
        fail("%s = %d but %s has %d names" % (size, getattr(mod, size), table, len(tables[table])))
if not np.array_equal(np.array(mod.kParamDefaults, dtype=np.float64), inputs["p"]):
    fail("kParamDefaults %s differ from the header's %s" % (mod.kParamDefaults, inputs["p"]))

t, x, u, p = inputs["t"][0], inputs["x"], inputs["u"], inputs["p"]
matrices = {"mass_matrix": (mod.kNdof, mod.kNdof), "constraint_jacobian": (mod.kNc, mod.kNuFull),
            "position_jacobian": (mod.kNposc, mod.kNqFull)}


def compare(function, got, status, expected):
    global checked
    if status != 0:
        fail("%s: the C++ reference returned status %d" % (function, status))
        return
    want_shape = matrices.get(function, (expected.size,))
    if got.shape != want_shape or got.dtype != np.float64:
        fail("%s: shape %s dtype %s, expected %s float64" % (function, got.shape, got.dtype, want_shape))
        return
    for a, b in zip(got.ravel(), expected):
        checked += 1
        if not abs(a - b) <= 1e-9 * max(1.0, abs(b)):
            fail("%s: %r from Python, %r from C++" % (function, a, b))


for function, (status, expected) in calls.items():
    if function == "rhs_partition":
        got = model.rhs_partition(0, t, x, u, p)
    elif function == "inverse_dynamics":
        # Its third argument is the kNdof independent accelerations, not the inputs.
        got = model.inverse_dynamics(t, x, inputs["zdot"], p)
    elif status == 4:
        # Not defined for this model: the status becomes ModelError naming it.
        try:
            getattr(model, function)(t, x, u, p)
            fail("%s: status 4 in C++ but no exception in Python" % function)
        except mod.ModelError as e:
            if e.status != 4 or "not defined" not in str(e):
                fail("%s: ModelError %r" % (function, str(e)))
        continue
    else:
        got = getattr(model, function)(t, x, u, p)
    compare(function, got, status, expected)

# The compressed rows of each Jacobian, expanded by the module's pattern, are its dense form.
for dense, prefix in (("constraint_jacobian", "kConstraintJacobian"), ("position_jacobian", "kPositionJacobian")):
    values = getattr(model, dense + "_values")(t, x, u, p)
    row_ptr, col_idx = getattr(mod, prefix + "RowPtr"), getattr(mod, prefix + "ColIdx")
    full = getattr(model, dense)(t, x, u, p)
    expanded = np.zeros(full.shape)
    for i in range(full.shape[0]):
        for k in range(row_ptr[i], row_ptr[i + 1]):
            expanded[i, col_idx[k]] = values[k]
    checked += full.size
    if len(values) != getattr(mod, prefix + "Nnz") or not np.array_equal(expanded, full):
        fail("%s: the compressed rows do not expand to the dense matrix" % dense)

# Defaults: p omitted means kParamDefaults; u omitted is allowed only without inputs.
if mod.kNin == 0:
    compare("rhs", model.rhs(t, x), *calls["rhs"])
    compare("rhs", model.rhs(t, list(x)), *calls["rhs"])  # any sequence of numbers
else:
    compare("rhs", model.rhs(t, x, u), *calls["rhs"])
    try:
        model.rhs(t, x)
        fail("rhs without u: no error for a model with %d inputs" % mod.kNin)
    except ValueError as e:
        if "u is required" not in str(e):
            fail("rhs without u: %s" % e)

# Shapes are checked.
for bad in (x[:-1], np.zeros((mod.kNx, 1))):
    try:
        model.rhs(t, bad, u, p)
        fail("rhs accepted an x of shape %s" % (bad.shape,))
    except ValueError as e:
        if "expected shape" not in str(e):
            fail("wrong x shape: %s" % e)

# A NaN parameter: status 2 from C++, ModelError from Python, naming the meaning.
if mod.kNp > 0:
    bad_p = p.copy()
    bad_p[0] = math.nan
    try:
        model.rhs(t, x, u, bad_p)
        fail("rhs with a NaN parameter raised nothing")
    except mod.ModelError as e:
        if e.status != 2 or e.function != "rhs" or "not finite" not in str(e):
            fail("NaN parameter: %r (status %d)" % (str(e), e.status))

# An index out of range for the partition dispatcher: status 3.
try:
    model.rhs_partition(mod.kNpartitions, t, x, u, p)
    fail("rhs_partition out of range raised nothing")
except mod.ModelError as e:
    if e.status != 3:
        fail("rhs_partition out of range: status %d" % e.status)

for f in failures:
    print("FAIL " + f)
print("checked %d values" % checked)
sys.exit(1 if failures else 0)
