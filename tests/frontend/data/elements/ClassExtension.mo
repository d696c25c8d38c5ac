// A class extension (MLS 7.3.1): `redeclare model extends M(k = 2)` in B is
// the M that B inherits from A, extended, modified and put in its place; the
// component `M m` that A declares is of B's M in an instance of B, and C
// extends B's M again. The function's algorithm comes from its extension.
model ClassExtension
  model A
    replaceable model M
      parameter Real k = 1;
      Real v;
    equation
      v = k * time;
    end M;
    replaceable partial function f
      input Real x;
      output Real y;
    end f;
    M m;
  end A;
  model B
    extends A;
    redeclare model extends M(k = 2)
      Real w = 10 * v;
    end M;
    redeclare function extends f
    algorithm
      y := 3 * x;
    end f;
    Real z = f(time);
  end B;
  model C
    extends B;
    redeclare model extends M
      Real u = w + 1;
    end M;
  end C;
  A a;
  B b;
  C c;
end ClassExtension;
