"""catc — the compiler for .cat robot-recomposition models.

Pipeline: text → parse tree → AST (spans) → checked IR (:mod:`catc.ir`) → view functor
(:mod:`catc.ir.views`) → encodings → solver → composition → validation → output.
"""

__version__ = "0.1.0"
