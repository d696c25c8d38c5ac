// Names in classes a package inherits are looked up in the package that
// inherits them (MLS 5.6.1, 7.1), as Modelica.Media's mediums need: in
// Liquid, Base's function h_T calls Liquid's redeclared h and builds Liquid's
// State (with its extra field); Base's model Props declares Liquid's State;
// Base's constants take the values Liquid's and Mixture's extends clauses
// give (nX from names, names from mediumName), read in the derived package.
// Base itself keeps its own classes and values. Gas puts its State in place
// by its extends clause's redeclaration, and declares h's input again.
model InheritedPackageLookup
  partial package Base
    constant String mediumName = "unnamed";
    constant String names[:] = {mediumName};
    constant Integer nX = size(names, 1);
    constant Real cp = 1;
    constant Real T0 = 273.15;
    replaceable record State
      Real T;
    end State;
    replaceable function h
      input State s;
      output Real y;
    algorithm
      y := cp * (s.T - T0);
    end h;
    function h_T
      input Real T;
      output Real y;
    algorithm
      y := h(State(T = T, p = 2));
    end h_T;
    replaceable model Props
      Real T = 300 + time;
      Real X[nX] = fill(1 / nX, nX);
      State state(T = T);
      Real y = h(state);
    end Props;
  end Base;
  package Liquid
    extends Base(mediumName = "water", cp = 4184);
    redeclare record extends State
      Real p;
    end State;
    redeclare function extends h
    algorithm
      y := cp * (s.T - T0) + s.p;
    end h;
    redeclare model extends Props
      Real p = 1e5;
    equation
      state.p = p;
    end Props;
  end Liquid;
  package Mixture
    extends Liquid(names = {"a", "b"}, T0 = 0);
  end Mixture;
  record GasState
    Real T;
    Real p;
  end GasState;
  package Gas
    extends Base(redeclare record State = GasState, cp = 2);
    redeclare function extends h
      input State s; // declared again as Base declares it: one input
    algorithm
      y := cp * s.T + s.p;
    end h;
  end Gas;
  package M = Mixture;
  Base.Props base;
  Liquid.Props liquid;
  M.Props mixture;
  Real yl = Liquid.h_T(time);
  Real ym = M.h_T(time);
  Real n = M.nX;
  Gas.Props gas;
  Real yg = Gas.h_T(time);
equation
  gas.state.p = 5;
end InheritedPackageLookup;
