"""The analysis tools: benchmark problems A, B, C (problems), the hard cases (hardcases), the
stability matrix (stability), the work-precision sweep (work_precision: one measured run in runs, the
scipy and MuJoCo peers in peers; its figure is drawn by viz.plots) and the cost of effects and of many
bodies (throughput).  They use the engine; the engine never uses them."""
