// expect: syntax error: 'when' not closed by 'end when;' before 'end when_without_end;'
model when_without_end
  discrete Real y(start = 0);
equation
  when time > 1 then
    y = 1;
end when_without_end;
