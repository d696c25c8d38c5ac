// This file starts with a UTF-8 byte-order mark, which the parser skips.
model ByteOrderMarked
  Real x(start = 3, fixed = true);
equation
  der(x) = -2 * x;
end ByteOrderMarked;
