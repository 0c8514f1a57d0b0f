"""Renderers of compositions: string diagrams (:mod:`catc.render.diagram`)."""
