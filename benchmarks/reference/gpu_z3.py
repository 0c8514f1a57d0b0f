"""A hand-written Z3 script for examples/gpu-allocation/max-confidence.cat — the reference
that `catc optimize` is compared with (benchmarks/reference_bench.py).  Same question,
written directly against the Z3 Python API the way a user would without catc: three steps,
one Bool per component and step, the GPU pool and the confidence as Reals, the detector's
memory m as one Real, maximise the final confidence.
"""

import z3

K = 3
COMPONENTS = ["slam", "vlm", "detector"]
FIXED = {"slam": 2.25, "vlm": 9.5}  # GPU memory of the two fixed-size components

o = z3.Optimize()
act = {c: [z3.Bool(f"{c}{t}") for t in range(K)] for c in COMPONENTS}
gpu = [z3.Real(f"gpu{t}") for t in range(K + 1)]
conf = [z3.Real(f"conf{t}") for t in range(K + 1)]
running = {c: [z3.Bool(f"{c}_running{t}") for t in range(K + 1)] for c in COMPONENTS}
m = z3.Real("m")  # the detector's memory, a free parameter in [1, 6] GB

o.add(m >= 1, m <= 6)
o.add(gpu[0] == 16, conf[0] == 0)
o.add([z3.Not(running[c][0]) for c in COMPONENTS])
for t in range(K + 1):
    o.add(gpu[t] >= 0)
for t in range(K):
    # every component reads and consumes the GPU pool: at most one of them per step
    o.add(z3.AtMost(*(act[c][t] for c in COMPONENTS), 1))
    need = {"slam": FIXED["slam"], "vlm": FIXED["vlm"], "detector": m}
    for c in COMPONENTS:
        o.add(z3.Implies(act[c][t], gpu[t] >= need[c]))
        o.add(running[c][t + 1] == z3.Or(running[c][t], act[c][t]))
    o.add(gpu[t + 1] == gpu[t] - z3.Sum([z3.If(act[c][t], need[c], 0) for c in COMPONENTS]))
    o.add(conf[t + 1] == z3.If(act["detector"][t], z3.Q(1, 2) + z3.Q(2, 25) * m, conf[t]))
for c in COMPONENTS:
    o.add(z3.AtMost(*act[c], 1))  # each component is used at most once
    o.add(running[c][K])  # the goal: all three running
o.maximize(conf[K])

if o.check() == z3.sat:
    model = o.model()
    print("optimum", model.eval(conf[K]).as_fraction())
    print("m", model.eval(m).as_fraction())
    for t in range(K):
        print(t + 1, " ".join(c for c in COMPONENTS if z3.is_true(model.eval(act[c][t]))))
else:
    print("unsat")
