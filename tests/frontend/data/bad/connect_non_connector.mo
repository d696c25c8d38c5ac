// expect: connect() arguments must be connectors; 'x' and 'y' are Real variables
model connect_non_connector
  Real x;
  Real y;
equation
  x = time;
  connect(x, y);
end connect_non_connector;
