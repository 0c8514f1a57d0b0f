"""Encodings of the IR: Z3 terms (:mod:`z3enc`) and SMT-LIB2 text (:mod:`smtlib`),
over the finite grounding of :mod:`grounding`."""
