int a_symbol() { return 0; }
