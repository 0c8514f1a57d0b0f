"""A hand-written Z3 script for examples/detection/person.cat — the reference that
`catc solve` is compared with (benchmarks/solve_bench.py).  Same model, written directly
against the Z3 Python API the way a user would without catc: three steps, one Bool per
component and step, the topic and class as small integers, RAM as a Real.
"""

import z3

K = 3
TOPICS = ["image-raw", "fresh-topic"]  # the domain's topic plus one reserve value
CLASSES = ["person", "fresh-class"]
PERSON = 0

s = z3.Solver()
mount = [z3.Bool(f"mount{t}") for t in range(K)]
driver = [z3.Bool(f"driver{t}") for t in range(K)]
detector = [z3.Bool(f"detector{t}") for t in range(K)]
out = [z3.Int(f"out{t}") for t in range(K)]
req = [z3.Real(f"req{t}") for t in range(K)]
inp = [z3.Int(f"in{t}") for t in range(K)]
target = [z3.Int(f"target{t}") for t in range(K)]
mounted = [z3.Bool(f"mounted{t}") for t in range(K + 1)]
ram = [z3.Real(f"ram{t}") for t in range(K + 1)]
topics = [[z3.Bool(f"topic{t}_{i}") for i in range(len(TOPICS))] for t in range(K + 1)]
detects = [[z3.Bool(f"detects{t}_{i}") for i in range(len(CLASSES))] for t in range(K + 1)]

s.add(z3.Not(mounted[0]), ram[0] == 16)
s.add([z3.Not(b) for b in topics[0] + detects[0]])
for t in range(K + 1):
    s.add(ram[t] >= 0)
for t in range(K):
    s.add(out[t] >= 0, out[t] < len(TOPICS), inp[t] >= 0, inp[t] < len(TOPICS))
    s.add(target[t] >= 0, target[t] < len(CLASSES), req[t] >= 0.5, req[t] <= 2)
    s.add(z3.Implies(mount[t], z3.Not(mounted[t])))
    s.add(z3.Implies(driver[t], z3.And(mounted[t], ram[t] >= req[t])))
    s.add(
        z3.Implies(
            detector[t], z3.And(ram[t] >= 4, z3.Or([z3.And(inp[t] == i, topics[t][i]) for i in range(len(TOPICS))]))
        )
    )
    # driver and detector both read and consume RAM: not in the same step
    s.add(z3.Not(z3.And(driver[t], detector[t])))
    s.add(mounted[t + 1] == z3.Or(mounted[t], mount[t]))
    s.add(ram[t + 1] == ram[t] - z3.If(driver[t], req[t], 0) - z3.If(detector[t], 4, 0))
    for i in range(len(TOPICS)):
        s.add(topics[t + 1][i] == z3.Or(topics[t][i], z3.And(driver[t], out[t] == i)))
    for i in range(len(CLASSES)):
        s.add(detects[t + 1][i] == z3.Or(detects[t][i], z3.And(detector[t], target[t] == i)))
for comp in (mount, driver, detector):
    s.add(z3.AtMost(*comp, 1))
s.add(detects[K][PERSON])

if s.check() == z3.sat:
    m = s.model()
    for t in range(K):
        names = [
            n
            for n, v in (("mount-rgb-camera", mount), ("camera-driver", driver), ("open-vocab-detector", detector))
            if z3.is_true(m.eval(v[t]))
        ]
        print(t + 1, " ".join(names))
else:
    print("unsat")
