"""Drawing: matplotlib plots of trajectories (plots) and the meshcat 3-D viewer (viewer; imports meshcat).
They read trajectories and never step physics; the engine never imports them."""
