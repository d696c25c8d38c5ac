// A for-loop left by `break` under a condition that varies in time (the
// MSL's Digital registers: `if clock_flag == 0 then break;` inside a loop
// over the bits): the statements after the break in the loop run only where
// it was not taken, the else-branch beside it is not affected. count is the
// largest k <= n with 1 + ... + k <= 10*time, s that sum, last = count.
model BreakOnSignal
  parameter Integer n = 4;
  Real threshold = 10 * time;
  Integer count;
  Integer last;
  Real s;
algorithm
  count := 0;
  last := 0;
  s := 0;
  for i in 1:n loop
    if s + i > threshold then
      break;
    else
      last := i;
    end if;
    s := s + i;
    count := count + 1;
  end for;
end BreakOnSignal;
