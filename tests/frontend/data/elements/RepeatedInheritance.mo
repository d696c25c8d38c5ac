// A base inherited along two paths is one set of elements (MLS 7.3): also
// when both paths modify it alike (the MSL's DynamicPipe gives PartialTwoPort
// the same `final exposesState = ...` through PartialStraightPipe and
// PartialTwoPortFlow), and an `outer` element two bases declare is one alias
// of the `inner` one. A function called as an equation, and as a statement
// inside a function, is inlined for its checks and adds no equation;
// ModelicaError in it (Modelica.Utilities.Streams.error) is a check too.
model RepeatedInheritance
  model Environment
    parameter Real g = 9.81;
  end Environment;
  partial model TwoPort
    parameter Boolean exposesState = false;
    outer Environment env;
    Real x(start = 1, fixed = true);
  end TwoPort;
  partial model Volume
    outer Environment env;
    Real m = 2 * env.g;
  end Volume;
  partial model StraightPipe
    extends TwoPort;
    parameter Integer structure = 1;
  end StraightPipe;
  partial model FlowModel
    extends TwoPort(final exposesState = structure == 2);
    extends Volume;
  end FlowModel;
  model Pipe
    extends StraightPipe(final exposesState = structure == 2, structure = 2);
    extends FlowModel;
  equation
    der(x) = if exposesState then -x else x;
  end Pipe;
  function error
    input String message;
    external "C" ModelicaError(message);
  end error;
  function checkPositive
    input Real v;
    input String name;
  algorithm
    if v <= 0 then
      error(name + " must be positive");
    end if;
  end checkPositive;
  function checked
    input Real v;
    output Real y;
  algorithm
    checkPositive(v, "v");
    y := 2 * v;
  end checked;
  inner Environment env(g = 10);
  Pipe pipe;
  Real y = checked(pipe.x);
equation
  checkPositive(pipe.m, "pipe.m");
end RepeatedInheritance;
