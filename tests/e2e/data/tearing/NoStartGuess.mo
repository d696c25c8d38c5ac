// StartGuessRoot without the start value: tearing chooses by structure alone.
model NoStartGuess
  output Real x;
  output Real y;
  Real s(start = 0, fixed = true);
equation
  y = 2*x + sin(time);
  x*y = 8 + time;
  der(s) = x;
end NoStartGuess;
