// Examples of the MSL's QuasiStationary library, unchanged (needs Modelica
// 3.2.2 on the library path): phasors as the operator record Complex, its
// connectors `connector ComplexOutput = output Complex`, and reference
// angles as overdetermined records whose connection graph has loops (each
// circuit is one), broken with equalityConstraint (tests/e2e/test_overconstrained.cpp).

// A voltage phasor of 1 V at a frequency ramped from 1e-6 to 2 Hz in 1 s
// across R = 0.1 Ω, L = 1/(2π) H and C = 1/(2π) F in series.
model SeriesResonance
  extends Modelica.Electrical.QuasiStationary.SinglePhase.Examples.SeriesResonance;
end SeriesResonance;

// A three-phase transformer Yd01 (100 V / 100 V, 30 kVA, v_sc = 5 %,
// P_sc = 300 W) between a star source and a star load of its rated
// impedance; its Delta connects its pins by connect()s inside an
// if-equation in a for-loop, which close loops of the graph.
model TransformerTestbench
  extends Modelica.Electrical.QuasiStationary.Machines.Examples.TransformerTestbench;
end TransformerTestbench;
