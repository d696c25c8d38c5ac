// Initial equations flatten like equations: an inherited section, an array
// equation expanded per element, and the section of the model itself.
partial model InitialBase
  parameter Real a = 2;
  Real x[2](each start = 1);
initial equation
  der(x) = zeros(2);
end InitialBase;

model InheritedInitial
  extends InitialBase;
  Real y(start = 0, fixed = false);
initial equation
  y = a;
equation
  der(x) = {1 - a * x[1], y - x[2]};
  der(y) = -y;
end InheritedInitial;
