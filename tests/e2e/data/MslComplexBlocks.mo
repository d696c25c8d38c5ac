// Examples of the MSL's ComplexBlocks, unchanged (needs Modelica 3.2.2 on the
// library path): Complex signals through connectors `connector ComplexInput =
// input Complex`, Complex arithmetic by Complex's operators
// (tests/e2e/test_complex_blocks.cpp).

// The Bode plot of H(jw) = 1 / (1 + 2 d jw + (jw)^2), d = 1/sqrt(2), over a
// logarithmic frequency sweep from 0.01 to 100 rad/s in 1 s.
model ShowTransferFunction
  extends Modelica.ComplexBlocks.Examples.ShowTransferFunction;
end ShowTransferFunction;
