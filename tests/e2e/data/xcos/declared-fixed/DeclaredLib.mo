// A block library of our own, written as Coselica writes its initial
// values: whether y is fixed is an expression of a parameter
// (tests/e2e/test_diagram_errors.cpp, "declared fixed flags").
package DeclaredLib
  model Doubler "dx/dt = -x, y = 2 x; y fixed when initType > 0"
    parameter Real initType = 0 "0: y is a guess, 1: y starts at y_start";
    parameter Real y_start = 4;
    Real x(start = 0);
    Real y(start = y_start, fixed = if initType > 0 then true else false);
  equation
    der(x) = -x;
    y = 2 * x;
  end Doubler;
end DeclaredLib;
