"""rpo.runtime.flight: processor-in-the-loop runs of an exported controller package on an emulated
Cortex-M (QEMU): the firmware build (:mod:`rpo.runtime.flight.build`) and the target
(:mod:`rpo.runtime.flight.target`)."""
