from catc.entry import main

main()
