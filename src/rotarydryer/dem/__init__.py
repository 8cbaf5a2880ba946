"""DEM bridge: LIGGGHTS decks for a periodic slice of a flighted drum, runs, and flight holdup from dumps."""
