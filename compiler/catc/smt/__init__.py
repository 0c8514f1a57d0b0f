"""Encodings of the IR: the encoder (:mod:`encoder`), SMT-LIB2 scripts (:mod:`script`,
:mod:`smtlib`) and solver backends, over the finite universes of symbolic sorts of
:mod:`finite` (finite grounding, paper Proposition 1 — not deployment grounding)."""
