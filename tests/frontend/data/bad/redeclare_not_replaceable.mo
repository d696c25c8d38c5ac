// expect: 'src' is redeclared but its declaration is not replaceable
model redeclare_not_replaceable
  block Source
    output Real y = 1;
  end Source;
  block Two
    output Real y = 2;
  end Two;
  model Holder
    Source src;
  end Holder;
  Holder h(redeclare Two src);
end redeclare_not_replaceable;
