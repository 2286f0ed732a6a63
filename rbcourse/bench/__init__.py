"""The analysis tools: benchmark problems A, B, C (problems), the hard cases (hardcases), the
stability matrix (stability), the work-precision sweep beside scipy and MuJoCo (work_precision) and
the cost of effects and of many bodies (throughput).  They use the engine; the engine never uses them."""
