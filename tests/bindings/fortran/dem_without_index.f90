! Error path: the time loop without ppohDEM_update_index (in a folder with the sample's inputs).
program dem_without_index
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
    call ppohDEM_setparameters(file_info, parameters)
    call ppohDEM_pre(file_info, parameters, particles, cells, walls, objects, counter)
    call ppohDEM_integrate_system(parameters, particles, cells, walls, objects)
end program
