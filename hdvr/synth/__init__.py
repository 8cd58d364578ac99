"""Synthetic dance data: choreographies of the nine genres, multi-dancer scenes, rendering, ground truth."""
