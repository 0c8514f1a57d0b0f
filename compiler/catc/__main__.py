from catc.interfaces.entry import main

main()
