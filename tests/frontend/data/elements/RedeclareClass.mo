// `replaceable model M = A constrainedby I` redeclared in a modifier
// (`redeclare model M = B`), by an element `redeclare model M = C(k = 5)` of a
// class extending the base, and a replaceable package whose members are
// found through the redeclared package.
model RedeclareClass
  partial model I
    parameter Real k = 1;
    Real y;
  end I;
  model A
    extends I;
  equation
    y = k;
  end A;
  model B
    extends I;
  equation
    y = 2 * k;
  end B;
  model C
    extends I;
  equation
    y = 3 * k;
  end C;
  package Units1
    type Len = Real(unit = "m");
  end Units1;
  package Units2
    type Len = Real(unit = "km");
  end Units2;
  model Holder
    replaceable model M = A constrainedby I;
    replaceable package U = Units1;
    M m;
    U.Len len = m.y;
  end Holder;
  model Derived
    extends Holder;
    redeclare model M = C(k = 5);
  end Derived;
  Holder h1;
  Holder h2(redeclare model M = B, redeclare package U = Units2);
  Derived d;
end RedeclareClass;
