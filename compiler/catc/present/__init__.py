"""Renderers of compositions: string diagrams (:mod:`catc.present.diagram`)."""
