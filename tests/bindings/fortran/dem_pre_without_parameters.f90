! Error path: ppohDEM_pre before ppohDEM_setparameters.
program dem_pre_without_parameters
    use ppohDEM_util
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    type(ppohDEM_cells) :: cells
    type(ppohDEM_walls) :: walls
    type(ppohDEM_objects) :: objects
    type(ppohDEM_counter) :: counter
    call ppohDEM_loadfileinfo(file_info)
    call ppohDEM_pre(file_info, parameters, particles, cells, walls, objects, counter)
end program
