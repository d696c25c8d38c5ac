// expect: class 'extends_self' extends itself
model extends_self
  extends extends_self;
  Real x;
equation
  x = time;
end extends_self;
