"""A hand-written Z3 script for examples/navigation/farthest.cat — the reference that
`catc optimize` is compared with (benchmarks/reference_bench.py).  Same question, written
directly against the Z3 Python API the way a user would without catc: one step, one Bool
for the move, its length d as a Real, maximise the distance travelled.
"""

import z3

K = 1
RESERVE = 10

o = z3.Optimize()
move = [z3.Bool(f"move{t}") for t in range(K)]
d = [z3.Real(f"d{t}") for t in range(K)]  # the move's length, a free parameter in [0, 1000] m
battery = [z3.Real(f"battery{t}") for t in range(K + 1)]
travelled = [z3.Real(f"travelled{t}") for t in range(K + 1)]

o.add(battery[0] == z3.Q(733, 10), travelled[0] == 0)
for t in range(K + 1):
    o.add(battery[t] >= 0)
for t in range(K):
    cost = 5 + z3.Q(4, 5) * d[t]
    o.add(d[t] >= 0, d[t] <= 1000)
    o.add(z3.Implies(move[t], battery[t] - cost >= RESERVE))
    o.add(battery[t + 1] == battery[t] - z3.If(move[t], cost, 0))
    o.add(travelled[t + 1] == travelled[t] + z3.If(move[t], d[t], 0))
o.add(z3.AtMost(*move, 1))  # the move is used at most once
o.add(travelled[K] > 0)  # the goal
o.maximize(travelled[K])

if o.check() == z3.sat:
    model = o.model()
    print("optimum", model.eval(travelled[K]).as_fraction())
    for t in range(K):
        if z3.is_true(model.eval(move[t])):
            print(t + 1, "move d =", model.eval(d[t]).as_fraction())
else:
    print("unsat")
