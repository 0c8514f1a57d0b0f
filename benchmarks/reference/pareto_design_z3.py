"""A hand-written Z3 script for `catc pareto examples/pareto-design/design.cat` — the reference
that the pareto row of benchmarks/startup_bench.py is compared with.  Same question, written
directly against the Z3 Python API the way a user would without catc: choose one
speech-to-text model and one vision-language model (one step: the two choices touch
different resources, so they run side by side); quality is MMMU × (1 − WER), written as that
product of the two chosen values (nonlinear, as in the model); latency and GPU memory are
the sums.  The Pareto front of (max quality, min latency, min GPU memory) is found by the
guided improvement algorithm (Rayside et al. 2009), with nothing but satisfiability checks on
one incremental solver: take any choice not dominated by a point found so far, move to one
that dominates it while there is one, record it, then require every later choice to be
strictly better than it in some objective.  It prints the 13 non-dominated points (sorted by
their values, as catc lists them) and the pair chosen for each.
"""

import z3

STT = {  # name: (word error rate, latency ms, GPU GB)
    "whisper-tiny": ("0.075", 120, 1),
    "whisper-base": ("0.050", 200, 1),
    "whisper-small": ("0.034", 450, 2),
    "whisper-medium": ("0.029", 1100, 5),
    "whisper-large-v2": ("0.027", 2100, 10),
}
VLM = {  # name: (MMMU, latency ms, GPU GB)
    "llava15-7b": ("0.353", 900, 14),
    "llava15-13b": ("0.364", 1600, 26),
    "qwen-vl-chat": ("0.359", 1200, 19),
    "qwen2-vl-2b": ("0.411", 450, 5),
    "qwen2-vl-7b": ("0.541", 1000, 16),
    "internvl2-2b": ("0.363", 420, 5),
    "internvl2-8b": ("0.512", 1100, 17),
    "minicpm-v26": ("0.498", 1050, 17),
    "phi35-vision": ("0.430", 700, 9),
    "idefics2-8b": ("0.430", 1150, 17),
    "paligemma-3b": ("0.349", 500, 6),
}

stt = {n: z3.Bool(n) for n in STT}
vlm = {n: z3.Bool(n) for n in VLM}
wer, mmmu = z3.Real("wer"), z3.Real("mmmu")
s = z3.Solver()
s.add(z3.PbEq([(b, 1) for b in stt.values()], 1), z3.PbEq([(b, 1) for b in vlm.values()], 1))
s.add(*(z3.Implies(stt[n], wer == z3.RealVal(w)) for n, (w, _, _) in STT.items()))
s.add(*(z3.Implies(vlm[n], mmmu == z3.RealVal(m)) for n, (m, _, _) in VLM.items()))
quality = mmmu * (1 - wer)
latency = z3.Sum([z3.If(stt[n], z3.RealVal(lat), 0) for n, (_, lat, _) in STT.items()]) + z3.Sum(
    [z3.If(vlm[n], z3.RealVal(lat), 0) for n, (_, lat, _) in VLM.items()]
)
gpu = z3.Sum([z3.If(stt[n], z3.RealVal(g), 0) for n, (_, _, g) in STT.items()]) + z3.Sum(
    [z3.If(vlm[n], z3.RealVal(g), 0) for n, (_, _, g) in VLM.items()]
)


def values(m):
    return tuple(m.eval(t, model_completion=True).as_fraction() for t in (quality, latency, gpu))


def as_good(v):
    return z3.And(quality >= v[0], latency <= v[1], gpu <= v[2])


def better(v):
    return z3.Or(quality > v[0], latency < v[1], gpu < v[2])


front = []
while s.check() == z3.sat:
    m = s.model()
    while True:  # climb: a choice dominating this one, while there is one
        s.push()
        s.add(as_good(values(m)), better(values(m)))
        if s.check() != z3.sat:
            s.pop()
            break
        m = s.model()
        s.pop()
    point = values(m)
    chosen = sorted(n for n, b in {**stt, **vlm}.items() if z3.is_true(m.eval(b, model_completion=True)))
    front.append((point, chosen))
    s.add(better(point))  # every later point improves on this one somewhere

for (q, lat, g), chosen in sorted(front):
    print(q, lat, g, " ".join(chosen))
print(len(front), "non-dominated points")
