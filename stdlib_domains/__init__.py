"""The standard library of .cat domains, importable by name with ``(:import NAME)``.

Each ``NAME.cat`` file in this folder defines ``(domain NAME)``.
"""
